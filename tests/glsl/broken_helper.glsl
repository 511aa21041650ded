// A syntax error on a known line (the one with the marker), for the error-location test; not formatted.
// clang-format off
float helper(float x) {
  float y = x * ;  // SYNTAX-ERROR-MARKER
  return y;
}
