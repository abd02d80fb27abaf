// Floor shading: a grid of voxel-length squares (every 10th line bolder) anti-aliased with
// screen-space derivatives, the robot's soft shadow, and a fade into the background far
// from the target. Compiled twice: FLOOR_UNSHADOWED for the floor outside the shadow map.
in vec3 v_world;

uniform bool u_lit;
uniform vec3 u_floor_color;   // sRGB (flat, unlit)
uniform vec3 u_floor_linear;  // the same, linear
uniform vec3 u_background_linear;
uniform vec3 u_light_dir;
uniform vec3 u_target;
uniform float u_grid;         // grid spacing, m
uniform float u_fade;         // distance from the target where the floor has faded, m

out vec4 frag_color;

void main() {
  if (!u_lit) {
    frag_color = vec4(u_floor_color, 1.0);
    return;
  }
  vec3 base = u_floor_linear;
  float minor = grid_line(v_world.xy, u_grid, 1.0);
  float major = grid_line(v_world.xy, u_grid * 10.0, 1.6);
  base *= 1.0 - 0.10 * minor - 0.16 * major;
#ifdef FLOOR_UNSHADOWED
  float vis = 1.0;  // outside the shadow map's footprint
#else
  float vis = light_visibility(v_world, 0.001);
#endif
  vec3 c = base * (0.62 + 0.38 * u_light_dir.z * mix(0.35, 1.0, vis));
  float r = length(v_world.xy - u_target.xy) / u_fade;
  float fade = smoothstep(0.45, 1.0, r);
  c = mix(c, u_background_linear, fade);
  frag_color = vec4(linear_to_srgb(c), 1.0);
}
