// For `make sketch`: the sketch is checked with the example settings (a config.h of your own
// next to the sketch is used instead when there is one).
#include "config.h.example"
