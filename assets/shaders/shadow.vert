// Depth-only pass from the key light: the voxel transform of box.vert.
layout(location = 0) in vec3 a_corner;
layout(location = 2) in vec3 i_center;
layout(location = 3) in vec4 i_orient;
layout(location = 4) in float i_edge;

uniform mat4 u_view_proj;

void main() {
  gl_Position = u_view_proj * vec4(i_center + quat_rotate(i_orient, a_corner * i_edge), 1.0);
}
