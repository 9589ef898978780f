/* SPDX-License-Identifier: MIT */
// cards_frag.glsl - one pixel of a card (docs/cards.md, steps 3 and 4, as cards_draw.c): the
// pixel's ray meets the card's plane (depth and texel position perspective-correct, with their
// derivatives), the Cycles CoC of that depth gives the disc, mapped into texels as an ellipse
// and cut into `strips` rectangles of the slices' exact areas, each integrated from the
// summed-area table. The table comes in two parts (libddof/src/cards_device.c): `table_hi`
// holds multiples of a power of two that stay exact in float through a box's four corners,
// `table_lo` the small rest, so an integer box's sum is exact; a rectangle's fractional edges
// are weighted single-column and single-row boxes. Blending composites the result under the
// nearer cards already drawn; a pixel they made opaque is skipped first.
uniform vec2 frame;          // width, height
uniform vec4 ray;            // ray_a, ray_bx, ray_c, ray_by (libddof/src/cards.h)
uniform vec4 lens;           // k_px, focus (m), pixel aspect, unused
uniform vec2 radius_limits;  // smallest and largest radius, px
uniform vec3 normal, origin, axis1, axis2;
uniform vec3 map_u, map_v;   // u, v = a0 + a1 s + a2 q
uniform ivec2 table_size;    // tw, th (the table is one larger each way)
uniform int strips;
uniform float line[65], mid[64], slice[64];
layout(binding = 0) uniform sampler2D table_hi;
layout(binding = 1) uniform sampler2D table_lo;
// The frame so far (the framebuffer's own texture, read under glTextureBarrier: each pixel is
// read and then written once per card, as ARB_texture_barrier allows): a pixel this opaque
// takes nothing from the cards behind, as on the CPU (cards_draw.c, CARDS_OPAQUE).
layout(binding = 2) uniform sampler2D frame_so_far;
layout(location = 0) out vec4 color;

// x (or y) clamped to the texture as a cell and the fraction into it (cards_draw.c table_at).
void table_at(float x, int size, out int cell, out float frac)
{
    x = clamp(x, 0.0, float(size));
    cell = min(int(x), size - 1);
    frac = x - float(cell);
}

// The integral over [xa, xb] x [ya, yb] (texels): the 16 corners' table entries, combined
// as 9 integer boxes (the whole cells, then each fractional column and row) whose sums are
// exact before they are weighted.
vec4 rectangle(float xa, float xb, float ya, float yb)
{
    int c[4], r[4];
    float fa, fb, fc, fd;
    table_at(xa, table_size.x, c[0], fa);
    table_at(xb, table_size.x, c[2], fb);
    table_at(ya, table_size.y, r[0], fc);
    table_at(yb, table_size.y, r[2], fd);
    c[1] = c[0] + 1;
    c[3] = c[2] + 1;
    r[1] = r[0] + 1;
    r[3] = r[2] + 1;
    vec4 hi[4][4], lo[4][4];
    for (int j = 0; j < 4; j++)
        for (int i = 0; i < 4; i++) {
            hi[j][i] = texelFetch(table_hi, ivec2(c[i], r[j]), 0);
            lo[j][i] = texelFetch(table_lo, ivec2(c[i], r[j]), 0);
        }
    // x parts: cells [c0, c2) weight 1, column c2 weight fb, column c0 weight -fa; y alike
    const int from[3] = int[3](0, 2, 0), to[3] = int[3](2, 3, 1);
    float wx[3] = float[3](1.0, fb, -fa), wy[3] = float[3](1.0, fd, -fc);
    vec4 total = vec4(0.0);
    for (int y = 0; y < 3; y++)
        for (int x = 0; x < 3; x++) {
            const int x0 = from[x], x1 = to[x], y0 = from[y], y1 = to[y];
            vec4 box = ((hi[y1][x1] - hi[y1][x0]) - (hi[y0][x1] - hi[y0][x0])) +
                       ((lo[y1][x1] - lo[y1][x0]) - (lo[y0][x1] - lo[y0][x0]));
            total += (wx[x] * wy[y]) * box;
        }
    return total;
}

void main()
{
    if (texelFetch(frame_so_far, ivec2(gl_FragCoord.xy), 0).a >= 1.0 - 1e-6)
        discard;
    const float x = gl_FragCoord.x, y = frame.y - gl_FragCoord.y; // pixels, y down
    const vec3 d = vec3(ray.x * x + ray.y, ray.w - ray.z * y, -1.0);
    const float w = dot(normal, d), inv_w = 1.0 / w, n_o = dot(normal, origin);
    const float z = n_o * inv_w;
    if (!(z > 0.0))
        discard;
    const float dzx = -z * normal.x * ray.x * inv_w, dzy = z * normal.y * ray.z * inv_w;
    const float de1 = dot(d, axis1), de2 = dot(d, axis2);
    const float s = z * de1 - dot(origin, axis1), q = z * de2 - dot(origin, axis2);
    const float s_x = dzx * de1 + z * ray.x * axis1.x, s_y = dzy * de1 - z * ray.z * axis1.y;
    const float q_x = dzx * de2 + z * ray.x * axis2.x, q_y = dzy * de2 - z * ray.z * axis2.y;
    const float tw = float(table_size.x), th = float(table_size.y), aspect = lens.z;
    const float t0 = tw * (map_u.x + map_u.y * s + map_u.z * q);
    const float t1 = th - th * (map_v.x + map_v.y * s + map_v.z * q);
    const float a0 = tw * (map_u.y * s_x + map_u.z * q_x);
    const float a1 = tw * (map_u.y * s_y + map_u.z * q_y) * aspect;
    const float b0 = -th * (map_v.y * s_x + map_v.z * q_x);
    const float b1 = -th * (map_v.y * s_y + map_v.z * q_y) * aspect;
    const float coc = lens.x * abs(1.0 - lens.y * w / n_o);
    const float r = clamp(0.5 * coc, radius_limits.x, radius_limits.y);
    const float det = abs(a0 * b1 - a1 * b0), bb = b0 * b0 + b1 * b1;
    const float area = 3.14159265358979 * r * r * det;
    if (!(area > 1e-12) || !(bb > 0.0))
        discard;
    const float reach_y = r * sqrt(bb), shear = (a0 * b0 + a1 * b1) / bb;
    const float half_width = 0.25 * float(strips) * r * r * det / reach_y;
    vec4 total = vec4(0.0);
    for (int k = 0; k < strips; k++) {
        const float xc = t0 + shear * reach_y * mid[k], hw = half_width * slice[k];
        total += rectangle(xc - hw, xc + hw, t1 + reach_y * line[k],
                           t1 + reach_y * line[k + 1]);
    }
    color = total / area;
}
