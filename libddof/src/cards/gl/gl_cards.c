/* SPDX-License-Identifier: MIT */
/* gl_cards.c - ddof_render_cards on the device (the seam's render_cards), the patent's way:
 * each card's expanded polygon drawn as a triangle fan (cards_vert.glsl), the
 * rasteriser covering its pixels, a fragment shader averaging the card's texture over each
 * pixel's disc (cards_frag.glsl), blending compositing the cards near to far, each
 * under the ones already drawn (source factor 1 - destination alpha, destination factor 1:
 * out += (1 - out.a) card, the CPU's operator), a pixel already opaque skipped by the shader
 * reading the frame so far (glTextureBarrier between cards). A float RGBA framebuffer holds
 * the frame; each card's table is uploaded once; one read-back at the end. */
#include "gl_cards.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static GLuint compile(const gl_functions *gl, GLenum kind, const char *name, char *message,
                      size_t size)
{
    const char *parts[2] = {"#version 450\n", gl_shader_text(name)};
    return gl_compile_shader(gl, kind, name, 2, parts, message, size);
}

/* The cards' program, built on first use and kept with the device. */
static GLuint cards_program(ddof_device *device, char *message, size_t size)
{
    if (device->cards_program)
        return device->cards_program;
    const gl_functions *gl = &device->gl;
    GLuint vert = compile(gl, GL_VERTEX_SHADER, "cards_vert.glsl", message, size);
    GLuint frag = vert ? compile(gl, GL_FRAGMENT_SHADER, "cards_frag.glsl", message, size) : 0;
    if (!frag) {
        if (vert)
            gl->DeleteShader(vert);
        return 0;
    }
    const GLuint shaders[2] = {vert, frag};
    device->cards_program = gl_link_program(gl, shaders, 2, "the cards' program", message, size);
    return device->cards_program;
}

static GLint at(const gl_functions *gl, GLuint program, const char *name)
{
    return gl->GetUniformLocation(program, name);
}

/* The frame's uniforms: the view, the lens, the strips. */
static void frame_uniforms(const gl_functions *gl, GLuint p, const adi_cards_request *r)
{
    gl->ProgramUniform2f(p, at(gl, p, "frame"), (float)r->width, (float)r->height);
    gl->ProgramUniform4d(p, at(gl, p, "ray"), r->ray_a, r->ray_bx, r->ray_c, r->ray_by);
    gl->ProgramUniform4f(p, at(gl, p, "lens"), (float)r->k_px, (float)r->focus_m,
                         (float)r->aspect, 0.0f);
    gl->ProgramUniform2f(p, at(gl, p, "radius_limits"), r->min_radius_px, r->max_radius_px);
    gl->ProgramUniform1i(p, at(gl, p, "strips"), (GLint)r->strips);
    float line[65], mid[64], slice[64]; /* the shader's strips are float */
    for (uint32_t k = 0; k <= r->strips; k++)
        line[k] = (float)r->line[k];
    for (uint32_t k = 0; k < r->strips; k++) {
        mid[k] = (float)r->mid[k];
        slice[k] = (float)r->slice[k];
    }
    gl->ProgramUniform1fv(p, at(gl, p, "line"), (GLsizei)r->strips + 1, line);
    gl->ProgramUniform1fv(p, at(gl, p, "mid"), (GLsizei)r->strips, mid);
    gl->ProgramUniform1fv(p, at(gl, p, "slice"), (GLsizei)r->strips, slice);
}

static void vec3_uniform(const gl_functions *gl, GLuint p, const char *name, const double *v)
{
    gl->ProgramUniform3d(p, at(gl, p, name), v[0], v[1], v[2]);
}

/* One card: its table into the two textures, its plane's uniforms, its polygon drawn. */
static void draw_card(const gl_functions *gl, GLuint p, const GLuint textures[2], GLuint vbo,
                      const adi_card *c)
{
    const float *parts[2] = {c->table_hi, c->table_lo};
    for (int t = 0; t < 2; t++) {
        gl->ActiveTexture(GL_TEXTURE0 + t);
        gl->BindTexture(GL_TEXTURE_2D, textures[t]);
        gl->TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, (GLsizei)c->tw + 1, (GLsizei)c->th + 1, 0,
                       GL_RGBA, GL_FLOAT, parts[t]);
    }
    vec3_uniform(gl, p, "normal", c->normal);
    vec3_uniform(gl, p, "origin", c->origin);
    vec3_uniform(gl, p, "axis1", c->e1);
    vec3_uniform(gl, p, "axis2", c->e2);
    vec3_uniform(gl, p, "map_u", c->uv_affine[0]);
    vec3_uniform(gl, p, "map_v", c->uv_affine[1]);
    gl->ProgramUniform2i(p, at(gl, p, "table_size"), (GLint)c->tw, (GLint)c->th);
    float expanded[DDOF_CARD_MAX_VERTICES][2]; /* vertex positions are float */
    for (uint32_t k = 0; k < c->vertex_count; k++) {
        expanded[k][0] = (float)c->expanded[k][0];
        expanded[k][1] = (float)c->expanded[k][1];
    }
    gl->BindBuffer(GL_ARRAY_BUFFER, vbo);
    gl->BufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(c->vertex_count * 2 * sizeof(float)),
                   expanded, GL_STREAM_DRAW);
    gl->VertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, NULL);
    gl->EnableVertexAttribArray(0);
    gl->DrawArrays(GL_TRIANGLE_FAN, 0, (GLsizei)c->vertex_count);
}

/* The framebuffer's pixels into out, rows turned over (GL's row 0 is the bottom). */
static ddof_status read_back(const gl_functions *gl, const adi_cards_request *r, char *message,
                             size_t size)
{
    const size_t row = (size_t)r->width * 4;
    float *pixels = malloc(row * r->height * sizeof *pixels);
    if (!pixels) {
        snprintf(message, size, "no memory to read the cards' frame back");
        return DDOF_ERROR_OUT_OF_MEMORY;
    }
    gl->BindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    gl->PixelStorei(GL_PACK_ALIGNMENT, 4);
    gl->ReadPixels(0, 0, (GLsizei)r->width, (GLsizei)r->height, GL_RGBA, GL_FLOAT, pixels);
    for (uint32_t y = 0; y < r->height; y++)
        memcpy(r->out + (size_t)y * r->out_stride, pixels + (size_t)(r->height - 1 - y) * row,
               row * sizeof *pixels);
    free(pixels);
    return DDOF_OK;
}

ddof_status gl_cards_render(ddof_device *device, const adi_cards_request *r, char *message,
                            size_t size)
{
    const gl_functions *gl = &device->gl;
    /* The frame is a texture, and each card's table one texel larger than its texture each
     * way: checked before GL is asked (which would fail with GL_INVALID_VALUE, 0x501). */
    GLint max_size = 0;
    gl->GetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size);
    if ((int64_t)r->width > max_size || (int64_t)r->height > max_size) {
        snprintf(message, size,
                 "the %ux%u frame is larger than this renderer's GL_MAX_TEXTURE_SIZE (%d): "
                 "draw the cards on the CPU backend", r->width, r->height, (int)max_size);
        return DDOF_ERROR_UNSUPPORTED;
    }
    GLuint program = cards_program(device, message, size);
    if (!program)
        return DDOF_ERROR_BACKEND_FAILED;
    GLuint target = 0, fbo = 0, vao = 0, vbo = 0, textures[2] = {0, 0};
    gl->GenTextures(1, &target);
    gl->BindTexture(GL_TEXTURE_2D, target);
    gl->TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, (GLsizei)r->width, (GLsizei)r->height, 0,
                   GL_RGBA, GL_FLOAT, NULL);
    gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    gl->GenFramebuffers(1, &fbo);
    gl->BindFramebuffer(GL_FRAMEBUFFER, fbo);
    gl->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, target, 0);
    ddof_status status = DDOF_OK;
    if (gl->CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        snprintf(message, size, "a %ux%u float framebuffer is not available", r->width,
                 r->height);
        status = DDOF_ERROR_BACKEND_FAILED;
    }
    gl->GenTextures(2, textures);
    for (int t = 0; t < 2; t++) {
        gl->BindTexture(GL_TEXTURE_2D, textures[t]);
        gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    }
    gl->GenVertexArrays(1, &vao);
    gl->BindVertexArray(vao);
    gl->GenBuffers(1, &vbo);
    gl->Viewport(0, 0, (GLsizei)r->width, (GLsizei)r->height);
    gl->ClearColor(0.0f, 0.0f, 0.0f, 0.0f);
    gl->Clear(GL_COLOR_BUFFER_BIT);
    gl->UseProgram(program);
    frame_uniforms(gl, program, r);
    gl->Enable(GL_BLEND);
    gl->BlendFunc(GL_ONE_MINUS_DST_ALPHA, GL_ONE);
    for (uint32_t i = 0; status == DDOF_OK && i < r->card_count; i++) {
        adi_card card;
        status = r->card(r->user, i, ADI_CARD_SPLIT_TABLE, &card);
        if (status != DDOF_OK)
            break;
        if ((int64_t)card.tw + 1 > max_size || (int64_t)card.th + 1 > max_size) {
            snprintf(message, size,
                     "a card's %ux%u texture needs a %ux%u summed-area table, larger than this "
                     "renderer's GL_MAX_TEXTURE_SIZE (%d): textures of at most %d px a side, "
                     "or the CPU backend", card.tw, card.th, card.tw + 1, card.th + 1,
                     (int)max_size, (int)max_size - 1);
            status = DDOF_ERROR_UNSUPPORTED;
            break;
        }
        /* the frame so far, read by the shader to skip opaque pixels (cards_frag.glsl) */
        gl->ActiveTexture(GL_TEXTURE2);
        gl->BindTexture(GL_TEXTURE_2D, target);
        draw_card(gl, program, textures, vbo, &card);
        gl->TextureBarrier(); /* the next card reads what this one wrote */
    }
    gl->Disable(GL_BLEND);
    if (status == DDOF_OK)
        status = read_back(gl, r, message, size);
    gl->BindVertexArray(0);
    gl->DeleteVertexArrays(1, &vao);
    gl->DeleteBuffers(1, &vbo);
    gl->BindFramebuffer(GL_FRAMEBUFFER, 0);
    gl->DeleteFramebuffers(1, &fbo);
    gl->DeleteTextures(2, textures);
    gl->DeleteTextures(1, &target);
    gl->UseProgram(0);
    return status;
}
