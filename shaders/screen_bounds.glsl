// Conservative screen rectangles for impostors. The fragment shaders intersect the exact shape, so a
// rectangle only has to contain every pixel centre whose ray can hit it: it is padded by two pixels
// to absorb float rounding and the rasteriser's sub-pixel snapping, and it becomes the whole screen
// whenever the shape reaches the plane of the eye (where a perspective projection has no bound).
#ifndef BRUME_SCREEN_BOUNDS_GLSL
#define BRUME_SCREEN_BOUNDS_GLSL

const vec4 FULL_SCREEN_RECT = vec4(-1.0, -1.0, 1.0, 1.0);

// Tangent slopes (s = lateral / depth) of the lines from the eye touching a circle at
// (lateral, depth) of radius r; depth > r is required.
vec2 tangent_slopes(float lateral, float depth, float r) {
    float denom = depth * depth - r * r;
    float root = r * sqrt(max(lateral * lateral + denom, 0.0));
    return vec2(lateral * depth - root, lateral * depth + root) / denom;
}

vec4 pad_rect(vec4 rect) {
    vec2 pad = 4.0 / vec2(frame.counts.xy);  // two pixels in NDC units
    return vec4(rect.xy - pad, rect.zw + pad);
}

// Rect (xmin, ymin, xmax, ymax) in Vulkan NDC (y down). Returns false when nothing can be visible.
bool sphere_screen_rect(vec3 centre, float radius, out vec4 rect) {
    vec3 v = centre - frame.eye.xyz;
    float depth = dot(v, frame.forward.xyz);
    if (depth < -radius) return false;                  // wholly behind the eye
    if (depth <= radius * 1.001 + 1e-6 * length(v)) {   // reaches the eye plane
        rect = FULL_SCREEN_RECT;
        return true;
    }
    float sx = frame.right.w, sy = frame.up.w;
    float lateral_x = dot(v, frame.right.xyz) / sx;
    float lateral_y = dot(v, frame.up.xyz) / sy;
    vec2 slopes_x = tangent_slopes(lateral_x, depth, radius) / sx;
    vec2 slopes_y = tangent_slopes(lateral_y, depth, radius) / sy;
    rect = pad_rect(vec4(slopes_x.x, -slopes_y.y, slopes_x.y, -slopes_y.x));
    return all(lessThan(rect.xy, vec2(1.0))) && all(greaterThan(rect.zw, vec2(-1.0)));
}

bool box_screen_rect(vec3 lo, vec3 hi, out vec4 rect) {
    float sx = frame.right.w, sy = frame.up.w;
    vec2 rmin = vec2(1e30), rmax = vec2(-1e30);
    bool all_behind = true, reaches_eye_plane = false;
    for (int k = 0; k < 8; ++k) {
        vec3 corner = vec3((k & 1) != 0 ? hi.x : lo.x, (k & 2) != 0 ? hi.y : lo.y, (k & 4) != 0 ? hi.z : lo.z);
        vec3 v = corner - frame.eye.xyz;
        float depth = dot(v, frame.forward.xyz);
        all_behind = all_behind && depth < 0.0;
        if (depth <= 1e-4 * length(v)) {  // a corner at or behind the eye plane: no finite bound
            reaches_eye_plane = true;
            continue;
        }
        vec2 ndc = vec2(dot(v, frame.right.xyz) / (sx * sx), -dot(v, frame.up.xyz) / (sy * sy)) / depth;
        rmin = min(rmin, ndc);
        rmax = max(rmax, ndc);
    }
    if (all_behind) return false;
    if (reaches_eye_plane) {
        rect = FULL_SCREEN_RECT;
        return true;
    }
    rect = pad_rect(vec4(rmin, rmax));
    return all(lessThan(rect.xy, vec2(1.0))) && all(greaterThan(rect.zw, vec2(-1.0)));
}

// Corner `vertex` (0..5, two triangles) of a rect, clamped to the screen.
vec4 rect_corner(vec4 rect, int vertex) {
    rect = clamp(rect, vec4(-1.0), vec4(1.0));
    const ivec2 corners[6] = ivec2[6](ivec2(0, 0), ivec2(1, 0), ivec2(0, 1), ivec2(0, 1), ivec2(1, 0), ivec2(1, 1));
    ivec2 c = corners[vertex];
    return vec4(c.x == 0 ? rect.x : rect.z, c.y == 0 ? rect.y : rect.w, 0.0, 1.0);
}

#endif
