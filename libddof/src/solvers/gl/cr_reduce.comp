/* SPDX-License-Identifier: MIT */
// cr_reduce.comp - one level of cyclic reduction (Kass, Lefohn, Owens 2006, fig. 5): row j of
// the next level is row 2j+1 of this one with rows 2j and 2j+2 eliminated. Level 0 is read
// from the image with its coefficients computed on the fly. One invocation per (row, line).
layout(local_size_x = 64) in;

void main()
{
    uint gid = global_id();
    uint ll = gid % u_batch_lines, j = gid / u_batch_lines;
    if (j >= u_dst_count)
        return;
    int i = int(2u * j + 1u);
    Row r = eliminate(level_row(ll, i), level_row(ll, i - 1), level_row(ll, i + 1));
    store_level(u_dst_off, ll, j, r);
}
