/* disc_kernel.c - the disc kernels' fitted tables and what the layers need to know of them. */
#include "disc_kernel.h"

#include <math.h>

/* Written by study/lens/fit_disc_kernel.py; one entry per DDOF_KERNEL_DISC_*, in order. */
static const disc_kernel disc_kernels[] = {
#include "disc_kernels.inc"
};

const disc_kernel *ddof_disc_kernel(ddof_kernel kernel)
{
    for (size_t i = 0; i < sizeof disc_kernels / sizeof disc_kernels[0]; i++)
        if (disc_kernels[i].id == kernel)
            return &disc_kernels[i];
    return NULL;
}

uint32_t ddof_kernel_reach_px(const disc_kernel *disc, float beta_scale, float coc)
{
    const float per_px = disc ? disc->reach : 12.0f * sqrtf(beta_scale);
    return (uint32_t)ceilf(per_px * coc) + 2;
}
