// The headers nearly every test source includes, compiled once per test target
// (target_precompile_headers in tests/CMakeLists.txt and tests/ui/CMakeLists.txt): parsing
// GoogleTest and the standard library was most of a test source's build time. Only headers from
// outside the project belong here, so that editing the renderer never rebuilds the header.
#pragma once

#include <gtest/gtest.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <string_view>
#include <thread>
#include <utility>
#include <vector>
