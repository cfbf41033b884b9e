#version 460
// Opaque pass: one screen-space rectangle per box, read straight from the box buffer.
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"
#include "screen_bounds.glsl"

layout(location = 0) flat out uint v_box;

void main() {
    v_box = gl_InstanceIndex;
    GpuBox box = boxes[gl_InstanceIndex];
    vec4 rect;
    bool visible = box_screen_rect(box.min_corner.xyz, box.max_corner.xyz, rect);
    gl_Position = visible ? rect_corner(rect, gl_VertexIndex) : vec4(2.0, 2.0, 0.0, 1.0);
}
