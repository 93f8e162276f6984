// One triangle over the whole viewport (no vertex buffer: gl_VertexID), for the accumulation and
// tone-map passes.
void main() {
  vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
  gl_Position = vec4(2.0 * p - 1.0, 0.0, 1.0);
}
