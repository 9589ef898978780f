/* SPDX-License-Identifier: MIT */
/* disc_kernel.h - the fitted tables of the disc (lens) kernel.
 *
 * The heat kernel (one real implicit step per axis) is a soft blob with long tails. A disc is
 * built instead from complex implicit steps (Garcia's complex-Gaussian idea carried over to
 * diffusion): per component c and axis, a chain of `steps` implicit steps with complex
 * conductances beta = kappa_cm * d^2 (d the link's CoC diameter, the smaller of its two pixels),
 * rows then columns, and the output is Re sum_c mix_c (columns_c rows_c x). Every step keeps each
 * line's sum and sum_c Re(mix_c) = 1, so flat regions stay flat and the energy is kept;
 * Re(kappa) > 0 keeps every solve diagonally dominant; a link of CoC 0 still decouples exactly.
 * A chain (a product of resolvents) rather than a sum of them: its 1-D profile is smooth at 0
 * where a sum of one-step kernels has a cusp, and the fits of sums end in huge cancelling weights
 * (see study/lens/fit_disc_kernel.py).
 * The tables are fitted offline by study/lens/fit_disc_kernel.py against an anti-aliased uniform
 * disc of diameter d (d = 12, 32 and 80 px) and written into disc_kernels.inc.
 */
#ifndef DDOF_DISC_KERNEL_H
#define DDOF_DISC_KERNEL_H

#include "ddof_backend_seam.h"

/* The table of a disc kernel; NULL for DDOF_KERNEL_HEAT or an unknown value. */
const disc_kernel *ddof_disc_kernel(ddof_kernel kernel);

/* How far a kernel carries a CoC: ddof_kernel_reach_px, in the seam's layer rules (the device
 * grows its areas by it too). */
#include "ddof_layer_rules.h"

#endif
