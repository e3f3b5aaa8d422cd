// Numbers as the user wrote them: results that convert an SI value back into the user's unit.
#pragma once

namespace gearnvh {

// `v` rounded to 12 significant digits: a value converted from SI back into the unit the user
// wrote it in (700 rpm -> rad/s -> rpm) reads as written, 700, not 700.0000000000001.
double AsWritten(double v);

// rad/s in rpm, AsWritten.
double Rpm(double rad_s);

}  // namespace gearnvh
