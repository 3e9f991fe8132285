#include "core/io/output_folder.h"

#include <cerrno>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace caustica {
namespace {

namespace fs = std::filesystem;

/// The real path of an open descriptor (/proc/self/fd), or "" when /proc cannot say.
fs::path real_path_of(int fd) {
    std::error_code ec;
    const fs::path real = fs::read_symlink("/proc/self/fd/" + std::to_string(fd), ec);
    return ec ? fs::path() : real;
}

/// Whether the real path `real` is the real folder `folder` or lies below it.
bool is_inside(const fs::path& real, const fs::path& folder) {
    if (real.empty() || folder.empty()) return false;
    const fs::path relative = real.lexically_relative(folder);
    return !relative.empty() && *relative.begin() != "..";
}

/// Throws OutputOutsideFolder unless the open folder `folder_fd` (real path `real_folder`) and the
/// name `name` in it lead inside the current folder. A name that is a symlink must lead to a file
/// inside too; one that leads nowhere (dangling) is no way out: the write renames over the name,
/// replacing a symlink instead of writing through it.
void check_inside_current_folder(int folder_fd, const fs::path& real_folder, const std::string& name,
                                 const std::string& shown) {
    std::error_code ec;
    const fs::path current = fs::current_path(ec);  // getcwd: a real path
    if (ec || real_folder.empty())
        throw OutputOutsideFolder("cannot check where '" + shown + "' leads (the current folder or /proc/self/fd cannot say)");
    const std::string outside = "', outside the current folder '" + current.string() + "'";
    if (!is_inside(real_folder, current))
        throw OutputOutsideFolder("'" + shown + "' leads to '" + (real_folder / name).string() + outside);
    struct stat link {};
    if (::fstatat(folder_fd, name.c_str(), &link, AT_SYMLINK_NOFOLLOW) != 0 || !S_ISLNK(link.st_mode)) return;
    const int file = ::openat(folder_fd, name.c_str(), O_PATH | O_CLOEXEC);
    if (file < 0) return;
    const fs::path real_file = real_path_of(file);
    ::close(file);
    if (!is_inside(real_file, current)) throw OutputOutsideFolder("'" + shown + "' leads to '" + real_file.string() + outside);
}

}  // namespace

OutputFolder::OutputFolder(const fs::path& target, OutputPlace place, const std::string& shown) {
    path_ = target.parent_path();
    fd_ = ::open(path_.c_str(), O_PATH | O_DIRECTORY | O_CLOEXEC);
    if (fd_ < 0) {
        error_ = errno;
        return;
    }
    if (place == OutputPlace::anywhere) return;
    path_ = real_path_of(fd_);
    try {
        check_inside_current_folder(fd_, path_, target.filename().string(), shown);
    } catch (...) {
        ::close(fd_);
        throw;
    }
}

OutputFolder::~OutputFolder() {
    if (fd_ >= 0) ::close(fd_);
}

std::string output_outside_current_folder(const std::string& path) {
    std::error_code ec;
    const fs::path target = fs::absolute(path, ec);
    if (ec) return {};
    try {
        const OutputFolder folder(target, OutputPlace::inside_current_folder, path);
    } catch (const OutputOutsideFolder& e) {
        return e.what();
    }
    return {};
}

}  // namespace caustica
