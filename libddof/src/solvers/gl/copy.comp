/* SPDX-License-Identifier: MIT */
// copy.comp - a pass over lines of one pixel (or with nothing to solve): y = x.
layout(local_size_x = 256) in;

void main()
{
    uint p = global_id();
    if (p >= u_n * u_lines)
        return;
    store_result(p, src[p]);
}
