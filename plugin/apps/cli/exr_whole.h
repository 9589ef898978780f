/* SPDX-License-Identifier: MIT */
/* exr_whole.h - whether an existing EXR holds all its pixel data, for --skip-existing: its
 * header opens AND every chunk its offset table lists lies within the file. A file cut after
 * its header (a copy or a disk that stopped part-way) has chunks past its end; telling that
 * reads the offset table and each chunk's few header bytes, not the pixels, so a resumed
 * sequence stays cheap to check. Uses OpenEXR's C API directly. */
#ifndef DDOF_CLI_EXR_WHOLE_H
#define DDOF_CLI_EXR_WHOLE_H

/* 1 when `path` is a scanline EXR whose every part's every chunk lies within the file; 0 when
 * it does not open, a chunk is missing or past the end, or a part is tiled or deep (not what
 * ddof writes: such a file is recomputed). */
int exr_file_whole(const char *path);

#endif
