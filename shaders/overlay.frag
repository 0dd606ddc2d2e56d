#version 330 core
// Flat colour; points are drawn as round dots.
in vec3 v_color;

uniform int u_round_points;

out vec4 frag_color;

void main() {
  if (u_round_points != 0 && length(gl_PointCoord - vec2(0.5)) > 0.5) discard;
  frag_color = vec4(v_color, 1.0);
}
