// Included twice by double_values.comp: #pragma once keeps the second copy out.
#pragma once

float scale(float x) {
  return FACTOR * x;
}
