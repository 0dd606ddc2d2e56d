#version 330 core
// One triangle covering the screen, generated from gl_VertexID (no vertex buffer).
out float v_height;

void main() {
  vec2 corner = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
  vec2 clip = corner * 2.0 - 1.0;
  v_height = corner.y;
  gl_Position = vec4(clip, 1.0, 1.0);
}
