// Includes the broken file from inside an include.
#include "broken_include.glsl"
