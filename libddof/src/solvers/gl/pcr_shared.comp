/* SPDX-License-Identifier: MIT */
// pcr_shared.comp - parallel cyclic reduction (Zhang, Cohen, Owens 2010) of one line in
// shared memory: one work group per line, every step one barrier-separated sweep in which each
// equation eliminates its neighbours at distance s = 1, 2, 4, ... After ceil(log2 m) steps
// every equation stands alone and its source value is its solution.
//
// A level of up to PCR_CAPACITY rows fits (7 floats a row: 28 KiB of the 32 KiB every GL 4.3
// implementation has). Longer lines are first reduced by cyclic reduction in global memory
// (cr_reduce) until a level fits, solved here, and substituted back (cr_back): the CR+PCR
// hybrid. The level comes from the image (u_level0) or from the pyramid.
#define PCR_THREADS 128u
#define PCR_CAPACITY 1024u
#define PCR_PER_THREAD (PCR_CAPACITY / PCR_THREADS)
layout(local_size_x = 128) in;

shared float s_a[PCR_CAPACITY];
shared float s_c[PCR_CAPACITY];
shared float s_e[PCR_CAPACITY];
shared vec4 s_u[PCR_CAPACITY];

Row shared_row(uint k)
{
    Row r;
    r.a = s_a[k];
    r.c = s_c[k];
    r.e = s_e[k];
    r.u = s_u[k];
    return r;
}

void put_row(uint k, Row r)
{
    s_a[k] = r.a;
    s_c[k] = r.c;
    s_e[k] = r.e;
    s_u[k] = r.u;
}

void main()
{
    uint ll = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    if (ll >= u_batch_lines) // the whole group leaves together: no barrier is skipped
        return;
    uint m = u_level0 != 0u ? u_n : u_src_count;
    uint t = gl_LocalInvocationID.x;
    for (uint k = t; k < m; k += PCR_THREADS)
        put_row(k, level_row(ll, int(k)));
    barrier();
    for (uint s = 1u; s < m; s *= 2u) {
        Row next[PCR_PER_THREAD];
        for (uint q = 0u; q < PCR_PER_THREAD; q++) {
            uint k = t + q * PCR_THREADS;
            if (k < m)
                next[q] = eliminate(shared_row(k), k >= s ? shared_row(k - s) : zero_row(),
                                    k + s < m ? shared_row(k + s) : zero_row());
        }
        barrier();
        for (uint q = 0u; q < PCR_PER_THREAD; q++) {
            uint k = t + q * PCR_THREADS;
            if (k < m)
                put_row(k, next[q]);
        }
        barrier();
    }
    for (uint k = t; k < m; k += PCR_THREADS)
        store_solution(ll, k, s_u[k]);
}
