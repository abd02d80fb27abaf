// The ground and obstacles, shaded as the floor (floor.frag) where they are level: the same
// grid of voxel-length squares, the robot's soft shadow and the fade into the background far
// from the target. The grid lies across each face's main axis (x-y on the ground and box
// tops, y-z or x-z on risers and box sides), and the key light falls by the face's normal
// instead of the floor's (0, 0, 1), so slopes and sides read by their shade. Compiled twice:
// WORLD_UNSHADOWED for the triangles outside the shadow map's footprint.
in vec3 v_world;
flat in vec3 v_normal;

uniform bool u_lit;
uniform vec3 u_color;         // sRGB (flat, unlit)
uniform vec3 u_color_linear;  // the same, linear
uniform vec3 u_background_linear;
uniform vec3 u_light_dir;
uniform vec3 u_target;
uniform float u_grid;         // grid spacing, m
uniform float u_fade;         // distance from the target where the floor has faded, m

out vec4 frag_color;

void main() {
  if (!u_lit) {
    frag_color = vec4(u_color, 1.0);
    return;
  }
  vec3 n = normalize(v_normal);
  vec3 a = abs(n);
  vec2 across = a.z >= a.x && a.z >= a.y ? v_world.xy : (a.x >= a.y ? v_world.yz : v_world.xz);
  vec3 base = u_color_linear;
  float minor = grid_line(across, u_grid, 1.0);
  float major = grid_line(across, u_grid * 10.0, 1.6);
  base *= 1.0 - 0.10 * minor - 0.16 * major;
#ifdef WORLD_UNSHADOWED
  float vis = 1.0;  // outside the shadow map's footprint
#else
  float vis = light_visibility(v_world, 0.001);
#endif
  float ndl = max(dot(n, u_light_dir), 0.0);
  vec3 c = base * (0.62 + 0.38 * ndl * mix(0.35, 1.0, vis));
  float r = length(v_world.xy - u_target.xy) / u_fade;
  float fade = smoothstep(0.45, 1.0, r);
  c = mix(c, u_background_linear, fade);
  frag_color = vec4(linear_to_srgb(c), 1.0);
}
