#include "core/lua/scene_files.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstring>

namespace caustica::scene_lua {
namespace {

namespace fs = std::filesystem;

/// Largest file a script may have read in one piece (further bounded by the memory budget).
constexpr std::uint64_t max_file_bytes = std::uint64_t(4) << 30;

bool is_within(const fs::path& root, const fs::path& path) {
    auto r = root.begin();
    auto p = path.begin();
    for (; r != root.end(); ++r, ++p) {
        if (r->empty()) continue;  // trailing separator
        if (p == path.end() || *r != *p) return false;
    }
    return true;
}

bool within_roots(const LoaderContext& ctx, const fs::path& path) {
    for (const fs::path& root : ctx.read_roots)
        if (is_within(root, path)) return true;
    return false;
}

const char* file_type_name(mode_t mode) {
    if (S_ISDIR(mode)) return "a folder";
    if (S_ISFIFO(mode)) return "a FIFO";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISSOCK(mode)) return "a socket";
    return "not a regular file";
}

std::string roots_text(const LoaderContext& ctx) {
    std::string text;
    for (const fs::path& root : ctx.read_roots) text += (text.empty() ? "" : ", ") + root.string();
    return text;
}

/// The real path of an open descriptor, or "" when /proc cannot say.
fs::path real_path_of(int fd) {
    const std::string link = "/proc/self/fd/" + std::to_string(fd);
    char buffer[PATH_MAX + 1];
    const ssize_t length = ::readlink(link.c_str(), buffer, PATH_MAX);
    if (length <= 0 || length >= PATH_MAX) return {};
    return fs::path(std::string(buffer, static_cast<std::size_t>(length)));
}

}  // namespace

FileDescriptor& FileDescriptor::operator=(FileDescriptor&& other) noexcept {
    if (this != &other) {
        if (fd_ >= 0) ::close(fd_);
        fd_ = other.release();
    }
    return *this;
}

FileDescriptor::~FileDescriptor() {
    if (fd_ >= 0) ::close(fd_);
}

SceneFile open_scene_file(const LoaderContext& ctx, const std::string& as_written) {
    if (as_written.empty()) throw InputError("the file name is empty");
    if (as_written.find('\0') != std::string::npos) throw InputError("the file name contains a NUL byte");
    fs::path path(as_written);
    if (path.is_relative()) path = ctx.scene_dir / path;
    path = path.lexically_normal();
    const std::string quoted = "'" + as_written + "'";
    const std::string outside =
        quoted + " is outside the scene folder (scenes may read only files under " + roots_text(ctx) +
        "; the user may allow more with --allow-read DIR)";
    // Names outside every root are refused the same way whether or not they exist, so that a
    // script cannot probe the rest of the file system through the messages.
    const bool lexically_inside = within_roots(ctx, path);

    struct stat before {};
    if (::stat(path.c_str(), &before) != 0) {
        if (!lexically_inside) throw InputError(outside);
        throw InputError("cannot open " + quoted + " (" + path.string() + "): " + std::strerror(errno));
    }
    if (!S_ISREG(before.st_mode)) {
        if (!lexically_inside) throw InputError(outside);
        throw InputError(quoted + " (" + path.string() + ") is " + file_type_name(before.st_mode) +
                         ": only regular files can be read");
    }
    // O_NONBLOCK: should the name now lead to a FIFO, opening it must not wait for a writer.
    FileDescriptor fd(::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOCTTY | O_NONBLOCK));
    if (fd.get() < 0) {
        if (!lexically_inside) throw InputError(outside);
        throw InputError("cannot open " + quoted + " (" + path.string() + "): " + std::strerror(errno));
    }
    struct stat opened {};
    if (::fstat(fd.get(), &opened) != 0 || !S_ISREG(opened.st_mode) || opened.st_dev != before.st_dev ||
        opened.st_ino != before.st_ino)
        throw InputError(quoted + " (" + path.string() + ") changed while it was being opened");
    const fs::path real = real_path_of(fd.get());
    if (real.empty())
        throw InputError("cannot check where " + quoted + " leads (/proc/self/fd is not available)");
    if (!within_roots(ctx, real)) throw InputError(outside);
    // Back to blocking reads (a regular file never blocks; this only undoes O_NONBLOCK).
    ::fcntl(fd.get(), F_SETFL, ::fcntl(fd.get(), F_GETFL) & ~O_NONBLOCK);

    SceneFile file;
    file.fd = std::move(fd);
    file.path = path.string();
    file.shown = quoted + " (" + path.string() + ")";
    file.size = static_cast<std::uint64_t>(opened.st_size);
    file.device = opened.st_dev;
    file.inode = opened.st_ino;
    return file;
}

std::string read_scene_file(LoaderContext& ctx, const SceneFile& file, const char* what) {
    if (file.size > max_file_bytes)
        throw InputError(file.shown + " is " + std::to_string(file.size >> 20) + " MiB, more than the " +
                         std::to_string(max_file_bytes >> 20) + " MiB a scene may read in one file");
    charge_memory(ctx, static_cast<std::size_t>(file.size), what);
    std::string text(static_cast<std::size_t>(file.size), '\0');
    std::size_t done = 0;
    while (done < text.size()) {
        const ssize_t got = ::pread(file.fd.get(), text.data() + done, text.size() - done, static_cast<off_t>(done));
        if (got < 0 && errno == EINTR) continue;
        if (got < 0) throw InputError("cannot read " + file.shown + ": " + std::strerror(errno));
        if (got == 0) throw InputError(file.shown + " shrank while it was being read");
        done += static_cast<std::size_t>(got);
        if (ctx.cancel && ctx.cancel->load(std::memory_order_relaxed)) throw InputError("interrupted");
    }
    char extra;
    if (::pread(file.fd.get(), &extra, 1, static_cast<off_t>(done)) > 0)
        throw InputError(file.shown + " grew while it was being read");
    return text;
}

std::string read_main_script(const std::string& path, std::size_t max_bytes) {
    FileDescriptor fd(::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOCTTY | O_NONBLOCK));
    if (fd.get() < 0) throw InputError("cannot open " + path + ": " + std::strerror(errno));
    struct stat info {};
    if (::fstat(fd.get(), &info) != 0) throw InputError("cannot read " + path + ": " + std::strerror(errno));
    if (!S_ISREG(info.st_mode))
        throw InputError(path + " is " + file_type_name(info.st_mode) + ": a scene must be a regular file");
    const auto size = static_cast<std::uint64_t>(info.st_size);
    if (max_bytes != 0 && size > max_bytes)
        throw InputError(path + " is larger than the script memory limit (" + std::to_string(max_bytes >> 20) + " MiB)");
    ::fcntl(fd.get(), F_SETFL, ::fcntl(fd.get(), F_GETFL) & ~O_NONBLOCK);
    std::string text(static_cast<std::size_t>(size), '\0');
    std::size_t done = 0;
    while (done < text.size()) {
        const ssize_t got = ::read(fd.get(), text.data() + done, text.size() - done);
        if (got < 0 && errno == EINTR) continue;
        if (got <= 0) throw InputError("cannot read " + path + (got < 0 ? std::string(": ") + std::strerror(errno) : ": it shrank"));
        done += static_cast<std::size_t>(got);
    }
    return text;
}

void charge_memory(LoaderContext& ctx, std::size_t bytes, const char* what) {
    if (ctx.memory_limit != 0 && (bytes > ctx.memory_limit || ctx.memory_used > ctx.memory_limit - bytes)) {
        note_memory_exceeded(ctx);
        throw InputError(std::string("the scene's memory budget of ") + std::to_string(ctx.memory_limit >> 20) +
                         " MiB is used up: " + what + " would take " + std::to_string((bytes + (1 << 20) - 1) >> 20) +
                         " MiB more, the Lua heap and scene data hold " + std::to_string(ctx.memory_used >> 20) +
                         " MiB (--script-memory sets the budget)");
    }
    ctx.memory_used += bytes;
}

std::size_t mesh_bytes(const MeshData& mesh) {
    return sizeof(MeshData) + mesh.path.capacity() + mesh.positions.capacity() * sizeof(glm::vec3) +
           mesh.triangles.capacity() * sizeof(glm::uvec3) + mesh.texcoords.capacity() * sizeof(glm::vec2);
}

fs::path real_folder(const std::string& folder, const char* what) {
    std::error_code error;
    const fs::path real = fs::canonical(folder, error);
    if (error) throw InputError(std::string(what) + " '" + folder + "': " + error.message());
    if (!fs::is_directory(real, error)) throw InputError(std::string(what) + " '" + folder + "' is not a folder");
    return real;
}

}  // namespace caustica::scene_lua
