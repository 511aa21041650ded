// A full-screen triangle at the far plane; the fragment shader turns each pixel into a view direction.
out vec2 v_ndc;

void main() {
  vec2 corner = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2)) * 2.0 - 1.0;
  v_ndc = corner;
  gl_Position = vec4(corner, 1.0, 1.0);
}
