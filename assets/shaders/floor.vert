// The floor: a large square at z = 0 around the camera target, drawn as pieces (corners
// given in world coordinates) so only the part under the shadow map pays for the lookup.
layout(location = 0) in vec3 a_corner;

uniform mat4 u_view_proj;

out vec3 v_world;

void main() {
  v_world = vec3(a_corner.xy, 0.0);
  gl_Position = u_view_proj * vec4(v_world, 1.0);
}
