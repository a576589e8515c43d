/* Includes the header but defines no entry point. */
#include "mimics.h"

int helper(int x) { return x + 1; }
