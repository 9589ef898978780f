/* SPDX-License-Identifier: MIT */
/* gl_cone_dilate.c - ../cone_dilate.c on a device-resident map (cone_dilate.comp): one
 * dispatch per band of rows, in pass order. */
#include "gl_passes.h"

/* Loop steps one invocation of cone_dilate.comp may run: llvmpipe stops a shader's loops
 * after 65,535 iterations of all of them together (measured: they then end silently), so a
 * band of rows stays well below that; each row is its width of steps plus its share of the
 * row links. A row longer than that runs alone, its run along the row in pieces of this many
 * steps, the first with the row's links (at most 8192 steps more). */
#define CONE_BAND_STEPS 32768u

/* One dispatch of cone_dilate.comp: `count` rows from `first` (pass order), each taking the
 * steps [run_first, run_first + run_count) of its run along the row. */
static void cone_dispatch(const gl_functions *gl, GLuint prog, const GLint at[4], uint32_t first,
                          uint32_t count, uint32_t run_first, uint32_t run_count)
{
    gl->ProgramUniform1ui(prog, at[0], first);
    gl->ProgramUniform1ui(prog, at[1], count);
    gl->ProgramUniform1ui(prog, at[2], run_first);
    gl->ProgramUniform1ui(prog, at[3], run_count);
    gl->DispatchCompute(1, 1, 1);
    gl->MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

/* cone_dilate.c on a map (gl_passes.h): the box at `base` (floats), rows `stride` apart;
 * both passes, one dispatch per band of rows (cone_dilate.comp). */
int gl_cone_dilate(ddof_device *device, GLuint buffer, uint32_t base, uint32_t width,
                   uint32_t height, uint32_t stride, float slope, char *message, size_t size)
{
    const gl_functions *gl = &device->gl;
    GLuint prog = gl_programs_get(gl, &device->programs, GL_PROG_CONE_DILATE, message, size);
    if (!prog)
        return 0;
    gl_bind(gl, 2, buffer);
    gl_uniform_u(gl, prog, "u_base", base);
    gl_uniform_u(gl, prog, "u_stride", stride);
    gl_uniform_u(gl, prog, "u_height", height);
    gl_uniform_u(gl, prog, "u_width", width);
    gl_uniform_f(gl, prog, "u_axial", slope);
    gl_uniform_f(gl, prog, "u_diagonal", slope * 1.41421356f);
    const uint32_t row_steps = width + width / 8 + 2; /* the run and the links, 8 lanes */
    const uint32_t run = width - 1;                   /* the run's steps along a row */
    const GLint at[4] = {gl->GetUniformLocation(prog, "u_first"),
                         gl->GetUniformLocation(prog, "u_count"),
                         gl->GetUniformLocation(prog, "u_run_first"),
                         gl->GetUniformLocation(prog, "u_run_count")};
    gl->UseProgram(prog);
    for (uint32_t pass = 0; pass < 2; pass++) {
        gl_uniform_u(gl, prog, "u_backward", pass);
        if (row_steps <= CONE_BAND_STEPS) {
            const uint32_t band = CONE_BAND_STEPS / row_steps;
            for (uint32_t i = 0; i < height; i += band)
                cone_dispatch(gl, prog, at, i, height - i < band ? height - i : band, 0, run);
            continue;
        }
        for (uint32_t i = 0; i < height; i++)
            for (uint32_t s = 0; s < run; s += CONE_BAND_STEPS)
                cone_dispatch(gl, prog, at, i, 1, s,
                              run - s < CONE_BAND_STEPS ? run - s : CONE_BAND_STEPS);
    }
    return 1;
}
