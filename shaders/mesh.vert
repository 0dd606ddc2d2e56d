#version 330 core
// u_model places a mesh in the world (a rigid motion: its 3x3 part also turns normals).
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in float a_scalar;  // per-vertex value for the heat map (strain)

uniform mat4 u_model;
uniform mat4 u_view;
uniform mat4 u_projection;

out vec3 v_position;
out vec3 v_local_position;
out vec3 v_normal;
out float v_scalar;

void main() {
  vec4 world = u_model * vec4(a_position, 1.0);
  v_position = world.xyz;
  v_local_position = a_position;
  v_normal = mat3(u_model) * a_normal;
  v_scalar = a_scalar;
  gl_Position = u_projection * u_view * world;
}
