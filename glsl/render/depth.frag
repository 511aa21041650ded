// Shadow-map pass: depth only, written by the rasteriser.
void main() {}
