// The floor's grid lines, prepended to fragment shaders after shadow_lookup.glsl (floor.frag,
// world.frag): how much of a line of the grid of `spacing` (m) lies on the point p (0..1),
// lines `width_px` wide, anti-aliased with screen-space derivatives.
float grid_line(vec2 p, float spacing, float width_px) {
  vec2 g = p / spacing;
  vec2 w = fwidth(g);
  vec2 d = abs(fract(g - 0.5) - 0.5) / max(w, vec2(1e-6));
  float line = 1.0 - min(min(d.x, d.y) / width_px, 1.0);
  // Lines thinner than a pixel apart would alias into grey noise: fade them out.
  float density = max(w.x, w.y);
  return line * (1.0 - smoothstep(0.25, 0.6, density));
}
