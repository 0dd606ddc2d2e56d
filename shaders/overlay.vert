#version 330 core
// Debug overlay: coloured lines and points in world coordinates.
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_color;
layout(location = 2) in float a_size;

uniform mat4 u_view_projection;
uniform float u_depth_bias;  // clip-space pull towards the camera, so lines on a surface stay visible
uniform float u_pixel_scale; // framebuffer pixels per window unit (high-DPI)

out vec3 v_color;

void main() {
  v_color = a_color;
  gl_Position = u_view_projection * vec4(a_position, 1.0);
  gl_Position.z -= u_depth_bias * gl_Position.w;
  gl_PointSize = a_size * u_pixel_scale;
}
