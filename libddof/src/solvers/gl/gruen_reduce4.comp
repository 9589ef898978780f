/* SPDX-License-Identifier: MIT */
// gruen_reduce4.comp - Gruen's initial four-to-one reduction (Game Engine Gems 2, ch. 8): level
// 2 row j straight from image pixels 4j .. 4j+6, coefficients computed on the fly from the
// CoC (8 links, 7 gammas), without storing level 0 or level 1. One invocation per (row, line).
layout(local_size_x = 64) in;

// Level-0 row i with its links given; a zero row past the end.
Row row_from(uint line, int i, float a, float c)
{
    if (uint(i) >= u_n)
        return zero_row();
    uint p = pixel(line, uint(i));
    Row r;
    r.a = a;
    r.c = c;
    r.e = heat_at(p);
    r.u = src[p];
    return r;
}

void main()
{
    uint gid = global_id();
    uint ll = gid % u_batch_lines, j = gid / u_batch_lines;
    if (j >= u_dst_count)
        return;
    uint line = u_line0 + ll;
    int base = int(4u * j);
    // Links 4j-1 .. 4j+6, read once; level-0 rows 4j .. 4j+6 from them. Plain variables, no
    // arrays of structs: llvmpipe (Mesa 22.3) miscompiled a loop filling a Row[3].
    float l[8];
    for (int k = 0; k < 8; k++)
        l[k] = link_beta(line, base - 1 + k);
    Row r[7];
    r[0] = row_from(line, base + 0, l[0], l[1]);
    r[1] = row_from(line, base + 1, l[1], l[2]);
    r[2] = row_from(line, base + 2, l[2], l[3]);
    r[3] = row_from(line, base + 3, l[3], l[4]);
    r[4] = row_from(line, base + 4, l[4], l[5]);
    r[5] = row_from(line, base + 5, l[5], l[6]);
    r[6] = row_from(line, base + 6, l[6], l[7]);
    // Level-1 rows 2j, 2j+1, 2j+2 are image rows 4j+1, 4j+3, 4j+5 (level 1 has n/2 rows).
    uint m1 = u_n / 2u;
    Row l1a = 2u * j < m1 ? eliminate(r[1], r[0], r[2]) : zero_row();
    Row l1b = 2u * j + 1u < m1 ? eliminate(r[3], r[2], r[4]) : zero_row();
    Row l1c = 2u * j + 2u < m1 ? eliminate(r[5], r[4], r[6]) : zero_row();
    store_level(u_dst_off, ll, j, eliminate(l1b, l1a, l1c));
}
