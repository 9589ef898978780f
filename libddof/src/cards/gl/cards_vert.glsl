/* SPDX-License-Identifier: MIT */
// cards_vert.glsl - a card's expanded polygon (docs/cards.md, step 2; the core offsets each
// edge by its vertices' CoC radii) placed on the frame: pixels (x right, y down) to clip space.
// The rasteriser then covers exactly the pixels whose centres lie inside it, as the CPU does.
layout(location = 0) in vec2 pixel;
uniform vec2 frame; // width, height in pixels

void main()
{
    gl_Position = vec4(2.0 * pixel.x / frame.x - 1.0, 1.0 - 2.0 * pixel.y / frame.y, 0.0, 1.0);
}
