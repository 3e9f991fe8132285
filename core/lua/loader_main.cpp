// caustica-scene-loader: runs one scene script for load_scene_script (core/lua/scene_process.cpp)
// and is of no use on its own.
#include "core/lua/loader_child.h"

int main() { return caustica::scene_lua::run_loader_child(); }
