// A voxel: the unit cube [-0.5, 0.5]^3 scaled by its edge, rotated by its orientation and
// moved to its centre (one instance per voxel).
layout(location = 0) in vec3 a_corner;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec3 i_center;
layout(location = 3) in vec4 i_orient;  // quaternion (x, y, z, w)
layout(location = 4) in float i_edge;
layout(location = 5) in vec3 i_color;   // sRGB

uniform mat4 u_view_proj;

out vec3 v_world;
out vec3 v_normal;
out vec3 v_local;
flat out vec3 v_color;         // sRGB as given
flat out vec3 v_color_linear;  // linear, for lighting

void main() {
  v_local = a_corner;
  v_world = i_center + quat_rotate(i_orient, a_corner * i_edge);
  v_normal = quat_rotate(i_orient, a_normal);
  v_color = i_color;
  v_color_linear = srgb_to_linear(i_color);
  gl_Position = u_view_proj * vec4(v_world, 1.0);
}
