// Files a scene script names (io.open, io.lines, require, gr.mesh, gr.texture, gr.bumpmap): read
// only when they are regular files whose real path lies under the scene's folder or a folder the
// user allowed with --allow-read. The file is opened first and the opened file's real path is
// checked (through /proc/self/fd), so no symlink, `..` or race can lead the check and the read
// to different files.
#pragma once

#include "core/lua/lua_context.h"

#include <sys/types.h>

#include <algorithm>
#include <cstdint>
#include <string>

namespace caustica::scene_lua {

/// An open file descriptor, closed on destruction.
class FileDescriptor {
public:
    FileDescriptor() = default;
    explicit FileDescriptor(int fd) : fd_(fd) {}
    FileDescriptor(FileDescriptor&& other) noexcept : fd_(other.release()) {}
    FileDescriptor& operator=(FileDescriptor&& other) noexcept;
    FileDescriptor(const FileDescriptor&) = delete;
    FileDescriptor& operator=(const FileDescriptor&) = delete;
    ~FileDescriptor();

    int get() const { return fd_; }
    int release() {
        const int fd = fd_;
        fd_ = -1;
        return fd;
    }

private:
    int fd_ = -1;
};

/// A scene file, open for reading and checked.
struct SceneFile {
    FileDescriptor fd;
    std::string path;         ///< absolute and normalised, as named (symlinks not resolved)
    std::string shown;        ///< the name for messages: as written, with the resolved path
    std::uint64_t size = 0;   ///< bytes on disk when opened
    dev_t device = 0;         ///< identity of the file (the same file under two names is one)
    ino_t inode = 0;

};

/// Opens `as_written` (relative to the scene folder) for reading. Throws InputError without a
/// location ("'x.obj' is outside the scene folder ...", "'fifo' is not a regular file (a FIFO)").
SceneFile open_scene_file(const LoaderContext& ctx, const std::string& as_written);

/// Reads the whole of an opened scene file, charging its size to the script's memory budget
/// first; `what` names the use in budget messages ("mesh file"). Throws InputError.
std::string read_scene_file(LoaderContext& ctx, const SceneFile& file, const char* what);

/// Reads the main script the user named (any folder; a regular file of at most `max_bytes`).
/// Throws InputError naming `path`.
std::string read_main_script(const std::string& path, std::size_t max_bytes);

/// Charges `bytes` that the script makes the C++ side hold (names, snapshots, meshes, images) to
/// the same budget as the Lua heap. Throws InputError naming the budget and `what` when it is
/// used up (the guard adds "file:line: call:").
void charge_memory(LoaderContext& ctx, std::size_t bytes, const char* what);

/// Gives back `bytes` charged earlier for something now freed (a file's text once parsed).
inline void release_memory(LoaderContext& ctx, std::size_t bytes) {
    ctx.memory_used -= std::min(ctx.memory_used, bytes);
}

/// Charges appending one element to `items`, a vector of ctx.scene: the buffer it grows into when
/// it is full (libstdc++ doubles it) and `extra` heap bytes the element owns; the snapshot
/// estimate grows by the element alone. Call it before the push_back.
template <class T>
void charge_append(LoaderContext& ctx, const std::vector<T>& items, std::size_t extra, const char* what) {
    if (items.size() == items.capacity()) charge_memory(ctx, std::max<std::size_t>(1, items.capacity()) * sizeof(T), what);
    charge_memory(ctx, extra, what);
    ctx.scene_bytes += sizeof(T) + extra;
}

/// Makes `folder` a read root: its real path, checked to be a folder. Throws InputError.
std::filesystem::path real_folder(const std::string& folder, const char* what);

}  // namespace caustica::scene_lua
