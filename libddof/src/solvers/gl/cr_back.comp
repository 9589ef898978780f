/* SPDX-License-Identifier: MIT */
// cr_back.comp - one level of back-substitution: odd rows take their solution from the level
// above, even rows solve their own equation with those as neighbours (solver_cr.c). At level 0
// the solution goes into the image. One invocation per (row, line).
layout(local_size_x = 64) in;

uniform uint u_up_off;   // the level above, already solved
uniform uint u_up_count;

vec4 up_value(uint ll, int j)
{
    return load_level(u_up_off, u_up_count, ll, j).u; // 0 for a row that does not exist
}

void main()
{
    uint gid = global_id();
    uint ll = gid % u_batch_lines, j = gid / u_batch_lines;
    uint count = u_level0 != 0u ? u_n : u_src_count;
    if (j >= count)
        return;
    vec4 y;
    if ((j & 1u) != 0u)
        y = up_value(ll, int(j / 2u));
    else
        y = substitute(level_row(ll, int(j)), up_value(ll, int(j / 2u) - 1),
                       up_value(ll, int(j / 2u)));
    store_solution(ll, j, y);
}
