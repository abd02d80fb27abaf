// Post-process anti-aliasing: one triangle covering the viewport (corners at clip-space
// (-1, -1), (3, -1), (-1, 3)); the fragment shader reads the image by pixel position.
layout(location = 0) in vec3 a_corner;

void main() {
  gl_Position = vec4(a_corner.xy, 0.0, 1.0);
}
