// An include with a compile error on a known line (the test finds the marker).

float broken_helper(float x) {
    float y = x * 2.0;
    return y + missing_symbol; // ERROR HERE
}
