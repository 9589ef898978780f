/* SPDX-License-Identifier: MIT */
// unpack.comp - the working image back into the caller's layout (channels and row stride),
// ready to be read back; the padding between rows is never written.
layout(local_size_x = 256) in;

layout(std430, binding = 3) readonly buffer Values { vec4 values[]; };
layout(std430, binding = 7) writeonly buffer RawOut { float raw_out[]; };

uniform uint u_width;
uniform uint u_height;
uniform uint u_channels;
uniform uint u_out_offset; // floats before the first pixel (device-resident images)
uniform uint u_out_stride; // floats

void main()
{
    uint p = global_id();
    if (p >= u_width * u_height)
        return;
    uint x = p % u_width, y = p / u_width;
    vec4 v = values[p];
    for (uint c = 0u; c < u_channels; c++)
        raw_out[u_out_offset + y * u_out_stride + x * u_channels + c] = v[c];
}
