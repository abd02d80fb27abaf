// Soft-shadow lookup, prepended to fragment shaders after common.glsl.
uniform sampler2DShadow u_shadow_map;
uniform mat4 u_light_view_proj;
uniform bool u_shadows;
uniform float u_shadow_texel;  // 1 / shadow-map size

// Fraction of the key light reaching a world point: 16 fixed taps (a rotated grid) of
// hardware 2x2 depth comparisons, about 5 texels wide, so the shadow's edge is soft.
float light_visibility(vec3 world, float bias) {
  if (!u_shadows) return 1.0;
  vec4 p = u_light_view_proj * vec4(world, 1.0);
  vec3 s = p.xyz / p.w * 0.5 + 0.5;
  if (s.x <= 0.0 || s.x >= 1.0 || s.y <= 0.0 || s.y >= 1.0 || s.z >= 1.0) return 1.0;
  float sum = 0.0;
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      vec2 o = vec2(float(i) - 1.5, float(j) - 1.5);
      o = vec2(o.x * 0.92 - o.y * 0.38, o.x * 0.38 + o.y * 0.92) * 1.6;
      sum += texture(u_shadow_map, vec3(s.xy + o * u_shadow_texel, s.z - bias));
    }
  }
  return sum / 16.0;
}
