#version 330 core
// Two-sided Blinn-Phong: the back of a triangle gets its own colour and the flipped normal.
// u_color_mode 1 replaces the base colour with a heat map of the vertex scalar (strain);
// 2 draws flat u_flat_color (wireframe lines).
in vec3 v_position;
in vec3 v_local_position;
in vec3 v_normal;
in float v_scalar;

uniform vec3 u_eye;          // camera position, world
uniform vec3 u_light_dir;    // unit direction towards the key light, world
uniform vec3 u_front_color;
uniform vec3 u_back_color;
uniform float u_shininess;
uniform float u_specular;
uniform float u_checker_size;  // > 0: a faint checkerboard of this size in the mesh's own frame
uniform int u_color_mode;      // 0 surface colours, 1 heat map, 2 flat colour
uniform float u_scalar_range;  // heat map: |scalar| at full colour
uniform vec3 u_flat_color;

out vec4 frag_color;

// Compression towards blue, stretch through yellow to red, rest a light grey.
vec3 heat_color(float value) {
  float t = clamp(value / max(u_scalar_range, 1e-9), -1.0, 1.0);
  vec3 rest = vec3(0.85);
  if (t < 0.0) return mix(rest, vec3(0.15, 0.35, 1.0), -t);
  vec3 yellow = vec3(1.0, 0.85, 0.1);
  return t < 0.5 ? mix(rest, yellow, 2.0 * t) : mix(yellow, vec3(0.9, 0.1, 0.1), 2.0 * t - 1.0);
}

void main() {
  if (u_color_mode == 2) {
    frag_color = vec4(u_flat_color, 1.0);
    return;
  }
  vec3 n = normalize(v_normal);
  vec3 base = u_front_color;
  if (!gl_FrontFacing) {
    n = -n;
    base = u_back_color;
  }
  if (u_color_mode == 1) base = heat_color(v_scalar);
  if (u_checker_size > 0.0) {
    ivec3 cell = ivec3(floor(v_local_position / u_checker_size));
    base *= ((cell.x + cell.y + cell.z) & 1) == 0 ? 1.05 : 0.95;
  }
  vec3 to_eye = normalize(u_eye - v_position);
  // Key light, a dimmer fill from the eye so nothing facing the camera is black, and ambient.
  float key = max(dot(n, u_light_dir), 0.0);
  float fill = max(dot(n, to_eye), 0.0);
  vec3 half_dir = normalize(u_light_dir + to_eye);
  float highlight = key > 0.0 ? pow(max(dot(n, half_dir), 0.0), u_shininess) : 0.0;
  vec3 color = base * (0.18 + 0.62 * key + 0.25 * fill) + vec3(u_specular * highlight);
  frag_color = vec4(clamp(color, 0.0, 1.0), 1.0);
}
