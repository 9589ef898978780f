/* SPDX-License-Identifier: MIT */
// prelude.glsl - prepended to every kernel (after "#version 450" and the program's defines).
// Helpers every kernel shares; no buffers here, so that each kernel declares only what it uses.

#define FLT_MIN 1.17549435e-38

// Counts above 65535 work groups are dispatched as a 2D grid (the per-dimension limit);
// this is the flat index of the invocation either way. A macro, because gl_WorkGroupSize only
// exists after the kernel's layout(local_size_x) declaration.
#define global_id() \
    (gl_GlobalInvocationID.y * (gl_NumWorkGroups.x * gl_WorkGroupSize.x) + gl_GlobalInvocationID.x)

// num / den for a share of a sum of non-negatives (num <= den), and 0 for 0 / 0: the diagonal
// of a row with no excess and no links (libddof/src/solvers/solver.h, solver_share). A comparison
// rather than clamping den to the smallest subnormal, because GPUs flush subnormals to zero.
float share(float num, float den)
{
    return den > 0.0 ? num / den : 0.0;
}
