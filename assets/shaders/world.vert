// The world beyond the floor: an environment's ground and obstacle boxes, as triangles
// given in world coordinates with their faces' normals (world_triangles in scene.hpp).
layout(location = 0) in vec3 a_corner;
layout(location = 1) in vec3 a_normal;

uniform mat4 u_view_proj;

out vec3 v_world;
flat out vec3 v_normal;

void main() {
  v_world = a_corner;
  v_normal = a_normal;
  gl_Position = u_view_proj * vec4(v_world, 1.0);
}
