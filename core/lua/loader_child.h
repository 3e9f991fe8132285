// The two ends of the loader process's protocol (core/lua/scene_process.cpp starts the process,
// core/lua/loader_child.cpp is its body). The parent hands the child three descriptors:
//   fd 3: the request (LoadSettings and the script's path), read to its end;
//   fd 4: the reply: an 8-byte length, a kind letter and its payload;
//   fd 5: a SharedProgress page the child keeps the script's current line in.
// Reply kinds: 'O' + scene bytes (scene_wire.h), 'E' + message (InputError), 'C' (cancelled),
// 'M' + message (out of memory, without location), 'X' + message (anything else). Messages are
// printable and at most printable_text_max_bytes(shown_message_limit) bytes
// (core/util/printable_text.h); the parent keeps no more of one than that.
#pragma once

#include "core/lua/scene_loader.h"

#include <string>
#include <string_view>

namespace caustica::scene_lua {

/// Where the script is, kept where the parent process can read it should it have to stop the
/// loader process from outside (a page shared between the two).
struct SharedProgress {
    int line = 0;
    char file[1024] = {};
};

inline constexpr int request_fd = 3;
inline constexpr int reply_fd = 4;
inline constexpr int progress_fd = 5;

/// Writes all `size` bytes (retrying short writes and EINTR); false on an error.
bool write_all(int fd, const char* data, std::size_t size);

/// The request as bytes.
std::string encode_load_request(const std::string& path, const LoadSettings& settings);

/// The body of caustica-scene-loader: reads the request, runs the script, writes the reply.
/// Returns the process's exit code.
int run_loader_child();

}  // namespace caustica::scene_lua
