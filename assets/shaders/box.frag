// Voxel shading: hemisphere ambient, a key light with a soft shadow, a faint highlight,
// and slightly darkened edges so neighbouring voxels of one colour stay distinguishable.
in vec3 v_world;
in vec3 v_normal;
in vec3 v_local;
flat in vec3 v_color;
flat in vec3 v_color_linear;

uniform bool u_lit;
uniform bool u_outlines;
uniform vec3 u_light_dir;  // towards the light, unit
uniform vec3 u_eye;

out vec4 frag_color;

void main() {
  if (!u_lit) {
    frag_color = vec4(v_color, 1.0);
    return;
  }
  vec3 n = normalize(v_normal);
  vec3 base = v_color_linear;
  float ndl = max(dot(n, u_light_dir), 0.0);
  float vis = ndl > 0.0 ? light_visibility(v_world, 0.0015 + 0.002 * (1.0 - ndl)) : 0.0;
  float sky = 0.5 + 0.5 * n.z;  // hemisphere: bright from above, dim from the floor
  vec3 ambient = base * mix(0.22, 0.45, sky);
  vec3 diffuse = base * 0.75 * ndl * vis;
  vec3 v = normalize(u_eye - v_world);
  vec3 h = normalize(v + u_light_dir);
  float spec = 0.06 * pow(max(dot(n, h), 0.0), 40.0) * vis;
  vec3 c = ambient + diffuse + vec3(spec);
  if (u_outlines) {
    // Distance to the face's nearest edge, as a fraction of the voxel edge.
    vec3 a = abs(v_local);
    vec3 an = abs(n);
    float e;
    if (an.x >= an.y && an.x >= an.z) e = 0.5 - max(a.y, a.z);
    else if (an.y >= an.z) e = 0.5 - max(a.x, a.z);
    else e = 0.5 - max(a.x, a.y);
    c *= mix(0.72, 1.0, smoothstep(0.0, 0.05, e));
  }
  frag_color = vec4(linear_to_srgb(c), 1.0);
}
