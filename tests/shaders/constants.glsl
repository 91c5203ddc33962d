// A valid include: several lines, so that a wrong #line after it would be noticed.
const float kHalf = 0.5;
const float kQuarter = 0.25;

float scaled(float x) {
    return x * kHalf + kQuarter;
}
