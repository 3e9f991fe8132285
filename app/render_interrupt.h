// Internal to `caustica render` (app/render_*.cpp): the flag the first Ctrl-C or SIGTERM sets
// (app/render_command.cpp handles the signals); planning, rendering and writing stop once it is set.
#pragma once

#include <atomic>

namespace caustica {

extern std::atomic<bool> interrupted;

}  // namespace caustica
