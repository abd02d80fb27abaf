// The floor: one large square at z = 0 around the camera target.
layout(location = 0) in vec3 a_corner;

uniform mat4 u_view_proj;
uniform vec3 u_floor_center;
uniform float u_floor_half;

out vec3 v_world;

void main() {
  v_world = vec3(u_floor_center.xy + a_corner.xy * u_floor_half, 0.0);
  gl_Position = u_view_proj * vec4(v_world, 1.0);
}
