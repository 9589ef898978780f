/* SPDX-License-Identifier: MIT */
/* disc_kernel.c - the disc kernels' fitted tables and what the layers need to know of them. */
#include "disc_kernel.h"
#include "ddof_output_struct.h"

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

ddof_status ddof_kernel_get_info(ddof_kernel kernel, ddof_kernel_info *info)
{
    if (!info)
        return DDOF_ERROR_NULL_POINTER;
    if (info->struct_size < DDOF_KERNEL_INFO_SIZE_0_4)
        return DDOF_ERROR_BAD_PARAMETER;
    if ((unsigned)kernel >= DDOF_KERNEL_COUNT_)
        return DDOF_ERROR_BAD_PARAMETER;
    const disc_kernel *disc = ddof_disc_kernel(kernel);
    const ddof_kernel_info full = {
        .struct_size = sizeof full,
        .components = disc ? disc->components : 0u,
        .steps = disc ? disc->steps : 0u,
        .reach_coc = disc ? disc->reach : 0.0f,
        .fit_snr_db = disc ? disc->snr_db : 0.0f,
    };
    ddof_write_output_struct(info, &full, sizeof full);
    return DDOF_OK;
}

ddof_status ddof_kernel_get_step(ddof_kernel kernel, uint32_t component, uint32_t step,
                                 float kappa[2], float mix[2])
{
    if (!kappa || !mix)
        return DDOF_ERROR_NULL_POINTER;
    const disc_kernel *disc = ddof_disc_kernel(kernel);
    if (!disc || component >= disc->components || step >= disc->steps)
        return DDOF_ERROR_BAD_PARAMETER;
    kappa[0] = disc->kappa[component][step][0];
    kappa[1] = disc->kappa[component][step][1];
    mix[0] = disc->mix[component][0];
    mix[1] = disc->mix[component][1];
    return DDOF_OK;
}
