// `caustica compare IMAGE REFERENCE`: the caustic error of an image against a reference, as
// docs/ACCURACY.md defines it, from the command line.
#pragma once

#include <string>
#include <vector>

namespace caustica {

/// Prints the error of IMAGE against REFERENCE (PNG, EXR or PFM each) and returns the exit code;
/// throws InputError for bad arguments and unreadable or mismatched files.
int run_compare_command(const std::vector<std::string>& args);

}  // namespace caustica
