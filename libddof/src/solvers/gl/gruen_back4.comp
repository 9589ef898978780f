/* SPDX-License-Identifier: MIT */
// gruen_back4.comp - Gruen's last back-substitution, level 2 to the image in one pass: each
// invocation finishes four pixels 4j .. 4j+3 from the level-2 solutions around them,
// recomputing the level-0 and level-1 coefficients on the fly. One invocation per (group, line).
layout(local_size_x = 64) in;

vec4 level2(uint ll, int j)
{
    return load_level(u_src_off, u_src_count, ll, j).u; // 0 for a row that does not exist
}

void main()
{
    uint gid = global_id();
    uint groups = (u_n + 3u) / 4u;
    uint ll = gid % u_batch_lines, j = gid / u_batch_lines;
    if (j >= groups)
        return;
    uint line = u_line0 + ll;
    int base = int(4u * j);
    int n = int(u_n);
    vec4 y_before = level2(ll, int(j) - 1); // pixel 4j-1: level-1 row 2j-1, level-2 row j-1
    vec4 y3 = level2(ll, int(j));           // pixel 4j+3: level-2 row j
    // Pixel 4j+1 is level-1 row 2j (even there): its own equation, level-1 neighbours from level 2.
    vec4 y1 = vec4(0.0);
    if (base + 1 < n) {
        Row l1 = eliminate(row0(line, base + 1), row0(line, base), row0(line, base + 2));
        y1 = substitute(l1, y_before, y3);
    }
    store_result(pixel(line, uint(base)), substitute(row0(line, base), y_before, y1));
    if (base + 1 < n)
        store_result(pixel(line, uint(base + 1)), y1);
    if (base + 2 < n)
        store_result(pixel(line, uint(base + 2)), substitute(row0(line, base + 2), y1, y3));
    if (base + 3 < n)
        store_result(pixel(line, uint(base + 3)), y3);
}
