// Every wall-clock bound the suite asserts goes through one factor: how much slower than the
// machine the bounds were set on this build and this machine run now. A sanitizer build runs
// instrumented code several times slower, a loaded or slower machine slower still; bounds that
// ignore either fail on the machine, not on the code (docs/RELIABILITY.md, "Time bounds").
#pragma once

namespace caustica::testing {

/// How much slower than the reference machine this one runs now (1 to 4), measured once per
/// process on every CPU the process may use; CAUSTICA_TIME_FACTOR, when set, replaces it.
double machine_factor();

/// The build's factor (12 under AddressSanitizer or ThreadSanitizer, else 1) times the machine's.
double time_factor();

/// A bound of `seconds` on the reference machine, on this one.
inline double time_bound(double seconds) { return seconds * time_factor(); }

}  // namespace caustica::testing
