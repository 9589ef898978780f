/* SPDX-License-Identifier: MIT */
// cards_frag.glsl - one pixel of a card (docs/cards.md, steps 3 and 4, as cards_draw.c): the
// pixel's ray meets the card's plane (depth and texel position perspective-correct, with their
// derivatives), the Cycles CoC of that depth gives the disc, mapped into texels as an ellipse
// and cut into `strips` rectangles of the slices' exact areas, each integrated from the
// summed-area table. The table comes in two parts (libddof/src/cards/cards_request.c): `table_hi`
// holds multiples of a power of two that stay exact in float through a box's four corners,
// `table_lo` the small rest, so an integer box's sum is exact; a rectangle's partly covered
// first and last columns and rows are single-column and single-row boxes weighted by the
// share covered. Blending composites the result under the nearer cards already drawn; a pixel
// they made opaque is skipped first.
uniform vec2 frame;          // width, height
uniform dvec4 ray;           // ray_a, ray_bx, ray_c, ray_by (libddof/src/cards/cards.h)
uniform vec4 lens;           // k_px, focus (m), pixel aspect, unused
uniform vec2 radius_limits;  // smallest and largest radius, px
uniform dvec3 normal, origin, axis1, axis2;
uniform dvec3 map_u, map_v;  // u, v = a0 + a1 s + a2 q
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

// The extent [centre + from, centre + to] along the table's x (or y), clamped to the texture
// (the table is constant beyond it: outside the card is transparent): its first cell c0 and
// last c2, and the shares of them it covers, w0 and w2 (every cell between wholly). The centre
// is a double and the shares come from its distance to a cell edge plus an offset, never as
// the difference of two float positions: a disc a small fraction of a texel wide (a texel
// covering many pixels) keeps its width's and its place's precision in any texture.
void span(double centre, float from, float to, int size, out int c0, out int c2, out float w0,
          out float w2)
{
    from = max(from, float(-centre));
    to = min(to, float(double(size) - centre));
    c0 = clamp(int(floor(centre + double(from))), 0, size - 1);
    c2 = clamp(int(floor(centre + double(to))), 0, size - 1);
    if (!(to > from)) {
        c2 = c0;
        w0 = 0.0;
        w2 = 0.0;
    } else if (c2 <= c0) {
        c2 = c0;
        w0 = to - from;
        w2 = 0.0;
    } else {
        w0 = float((double(c0 + 1) - centre) - double(from));
        w2 = float((centre - double(c2)) + double(to));
    }
}

// The integral over [xc + xa, xc + xb] x [yc + ya, yc + yb] (texels) from the table's 16
// entries at the cells' edges: 9 integer boxes (the first cell, the whole cells between, the
// last cell, each way) whose sums are exact, weighted by the shares covered (all >= 0).
vec4 rectangle(double xc, float xa, float xb, double yc, float ya, float yb)
{
    int c[4], r[4], c2, r2;
    float wx[3], wy[3];
    span(xc, xa, xb, table_size.x, c[0], c2, wx[0], wx[2]);
    span(yc, ya, yb, table_size.y, r[0], r2, wy[0], wy[2]);
    wx[1] = 1.0;
    wy[1] = 1.0;
    // edges: first cell [c0, c0 + 1), between [c0 + 1, c2), last [c2, c2 + 1); a span within
    // one cell has an empty middle and a last cell of share 0 (its box: any cell in the table)
    c[1] = c[0] + 1;
    c[2] = max(c2, c[1]);
    c[3] = min(c[2] + 1, table_size.x);
    r[1] = r[0] + 1;
    r[2] = max(r2, r[1]);
    r[3] = min(r[2] + 1, table_size.y);
    vec4 hi[4][4], lo[4][4];
    for (int j = 0; j < 4; j++)
        for (int i = 0; i < 4; i++) {
            hi[j][i] = texelFetch(table_hi, ivec2(c[i], r[j]), 0);
            lo[j][i] = texelFetch(table_lo, ivec2(c[i], r[j]), 0);
        }
    vec4 total = vec4(0.0);
    for (int y = 0; y < 3; y++)
        for (int x = 0; x < 3; x++) {
            const int x0 = x, x1 = x + 1, y0 = y, y1 = y + 1;
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
    // The ray's point on the plane and its texel position in double, as on the CPU: a float
    // position near texel 1024 is off by 6e-5 texel, a fifth of a small disc 55 px per texel
    // wide. The derivatives, the disc's shape and its sums stay float.
    const double x = double(gl_FragCoord.x), y = double(frame.y) - double(gl_FragCoord.y);
    const dvec3 d = dvec3(ray.x * x + ray.y, ray.w - ray.z * y, -1.0);
    const double w = dot(normal, d), n_o = dot(normal, origin);
    const double z = n_o / w;
    if (!(z > 0.0))
        discard;
    const double s = z * dot(d, axis1) - dot(origin, axis1);
    const double q = z * dot(d, axis2) - dot(origin, axis2);
    const double dtw = double(table_size.x), dth = double(table_size.y);
    const double t0 = dtw * (map_u.x + map_u.y * s + map_u.z * q);
    const double t1 = dth - dth * (map_v.x + map_v.y * s + map_v.z * q);
    const float zf = float(z), inv_w = float(1.0 / w), ra = float(ray.x), rc = float(ray.z);
    const vec3 nf = vec3(normal), e1 = vec3(axis1), e2 = vec3(axis2);
    const vec3 mu = vec3(map_u), mv = vec3(map_v);
    const float de1 = float(dot(d, axis1)), de2 = float(dot(d, axis2));
    const float dzx = -zf * nf.x * ra * inv_w, dzy = zf * nf.y * rc * inv_w;
    const float s_x = dzx * de1 + zf * ra * e1.x, s_y = dzy * de1 - zf * rc * e1.y;
    const float q_x = dzx * de2 + zf * ra * e2.x, q_y = dzy * de2 - zf * rc * e2.y;
    const float tw = float(table_size.x), th = float(table_size.y), aspect = lens.z;
    const float a0 = tw * (mu.y * s_x + mu.z * q_x);
    const float a1 = tw * (mu.y * s_y + mu.z * q_y) * aspect;
    const float b0 = -th * (mv.y * s_x + mv.z * q_x);
    const float b1 = -th * (mv.y * s_y + mv.z * q_y) * aspect;
    const float coc = lens.x * abs(1.0 - lens.y * float(w / n_o));
    const float r = clamp(0.5 * coc, radius_limits.x, radius_limits.y);
    const float det = abs(a0 * b1 - a1 * b0), bb = b0 * b0 + b1 * b1;
    const float area = 3.14159265358979 * r * r * det;
    if (!(area > 1e-12) || !(bb > 0.0))
        discard;
    const float reach_y = r * sqrt(bb), shear = (a0 * b0 + a1 * b1) / bb;
    const float half_width = 0.25 * float(strips) * r * r * det / reach_y;
    vec4 total = vec4(0.0);
    for (int k = 0; k < strips; k++) {
        const double xc = t0 + double(shear * reach_y * mid[k]);
        const float hw = half_width * slice[k];
        total += rectangle(xc, -hw, hw, t1, reach_y * line[k], reach_y * line[k + 1]);
    }
    color = total / area;
}
