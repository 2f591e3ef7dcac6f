// A camera's spectral sensitivities as the film's observer (--sensor FILE.csv): the film then
// holds raw camera RGB instead of CIE XYZ.
//
// File format (the format of the tables in spectra/): '#' comment lines (the first should name
// the source of the data), the header line `wavelength_nm,r,g,b`, then one row per wavelength
// in nm, increasing, within 360-830 nm (the film's range), with sensitivities >= 0. Between
// rows the curves are linear; outside the first and last row they are 0. Only the relative
// scale matters: the film divides by the integral of g, so a constant spectrum of 1 gives g = 1.
#pragma once
#include <string>
#include <string_view>

#include "spectral/observer.h"

namespace spt {

/// Parses a sensor table; `origin` names the text in messages. Throws std::runtime_error with
/// "origin:line:column: what is wrong".
Observer parse_sensor(std::string_view text, const std::string& origin);

/// Reads and parses the sensor file at `path` (errors as parse_sensor, or naming the file when
/// it cannot be read).
Observer load_sensor(const std::string& path);

}  // namespace spt
