/* SPDX-License-Identifier: MIT */
// pyramid.glsl - storage of the reduced levels of cyclic reduction (CR, the PCR hybrid and
// Gruen's solver). Level rows are laid out [level offset + j][line of the batch], so that
// neighbouring invocations (neighbouring lines) touch neighbouring memory in both passes.
//
// FLOAT: a row is two vec4 (a, c, e, -) and u.
// PACKED (Gruen, DDOF_PRECISION_PACKED_HALF): one RGBA32UI texel per row and channel group:
//   .x = a (float bits) with its low 6 mantissa bits carrying bits 0..5 of half(u.z)
//   .y = c with its low 5 bits carrying bits 6..10, .z = e with bits 11..15,
//   .w = packHalf2x16(u.x, u.y).
// The coefficients keep 17-18 mantissa bits (~1e-5 relative), the values are half floats
// (~5e-4 relative). Channel group 0 is u.xyz, group 1 is u.w (stored in the x slot).

uniform uint u_group;      // PACKED: which channel group this solve carries
uniform uint u_src_off;    // first row of the level read (or solved, going back)
uniform uint u_src_count;  // rows in it
uniform uint u_dst_off;    // first row of the level written (reduction)
uniform uint u_dst_count;
uniform uint u_level0;     // 1: the level read (reduction) or solved (back) is the image

#ifdef PACKED
layout(std430, binding = 5) buffer Pyramid { uvec4 pyr[]; };

vec4 group_in(vec3 v)
{
    return u_group == 0u ? vec4(v, 0.0) : vec4(0.0, 0.0, 0.0, v.x);
}

vec3 group_out(vec4 u)
{
    return u_group == 0u ? u.xyz : vec3(u.w, 0.0, 0.0);
}

uvec4 pack_row(float a, float c, float e, vec4 u)
{
    vec3 g = group_out(u);
    uint h = packHalf2x16(vec2(g.z, 0.0)) & 0xFFFFu;
    return uvec4((floatBitsToUint(a) & ~0x3Fu) | (h & 0x3Fu),
                 (floatBitsToUint(c) & ~0x1Fu) | ((h >> 6) & 0x1Fu),
                 (floatBitsToUint(e) & ~0x1Fu) | ((h >> 11) & 0x1Fu),
                 packHalf2x16(g.xy));
}

Row unpack_row(uvec4 t)
{
    Row r;
    r.a = uintBitsToFloat(t.x & ~0x3Fu);
    r.c = uintBitsToFloat(t.y & ~0x1Fu);
    r.e = uintBitsToFloat(t.z & ~0x1Fu);
    uint h = (t.x & 0x3Fu) | ((t.y & 0x1Fu) << 6) | ((t.z & 0x1Fu) << 11);
    r.u = group_in(vec3(unpackHalf2x16(t.w), unpackHalf2x16(h).x));
    return r;
}

Row load_level(uint off, uint count, uint ll, int j)
{
    if (j < 0 || uint(j) >= count)
        return zero_row();
    return unpack_row(pyr[(off + uint(j)) * u_batch_lines + ll]);
}

void store_level(uint off, uint ll, uint j, Row r)
{
    pyr[(off + j) * u_batch_lines + ll] = pack_row(r.a, r.c, r.e, r.u);
}

// Replaces a row's value by its solution (going back down the pyramid).
void store_value(uint off, uint ll, uint j, vec4 y)
{
    uint k = (off + j) * u_batch_lines + ll;
    Row r = unpack_row(pyr[k]);
    pyr[k] = pack_row(r.a, r.c, r.e, y);
}
#else
struct StoredRow {
    vec4 coef; // a, c, e, unused
    vec4 u;
};
layout(std430, binding = 5) buffer Pyramid { StoredRow pyr[]; };

Row load_level(uint off, uint count, uint ll, int j)
{
    if (j < 0 || uint(j) >= count)
        return zero_row();
    StoredRow s = pyr[(off + uint(j)) * u_batch_lines + ll];
    Row r;
    r.a = s.coef.x;
    r.c = s.coef.y;
    r.e = s.coef.z;
    r.u = s.u;
    return r;
}

void store_level(uint off, uint ll, uint j, Row r)
{
    pyr[(off + j) * u_batch_lines + ll] = StoredRow(vec4(r.a, r.c, r.e, 0.0), r.u);
}

void store_value(uint off, uint ll, uint j, vec4 y)
{
    pyr[(off + j) * u_batch_lines + ll].u = y;
}
#endif

// Row i of the level read: the image on the fly (level 0) or a stored level.
Row level_row(uint ll, int i)
{
    return u_level0 != 0u ? row0(u_line0 + ll, i) : load_level(u_src_off, u_src_count, ll, i);
}

// Writes the solution of row j of the level solved: into the image at level 0.
void store_solution(uint ll, uint j, vec4 y)
{
    if (u_level0 != 0u)
        store_result(pixel(u_line0 + ll, j), y);
    else
        store_value(u_src_off, ll, j, y);
}
