// Numeric constants shared by all shader parts.
#ifndef IBLX_LIB_CONSTANTS
#define IBLX_LIB_CONSTANTS
const float kPi = 3.14159265358979323846;
const float kInvPi = 0.31830988618379067154;
const float kTwoPi = 6.28318530717958647692;
const float kOneMinusEpsilon = 0.99999994;  // largest float below 1
#endif
