#include "fuzz/fuzz_support.h"

#include "fuzz/fuzz_targets.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <vector>

namespace caustica::fuzz {

namespace {

std::string removed_at_exit;

void remove_folder() {
    std::error_code ignored;
    if (!removed_at_exit.empty()) std::filesystem::remove_all(removed_at_exit, ignored);
}

}  // namespace

void fuzz_require(bool condition, const char* what) {
    if (condition) return;
    std::fprintf(stderr, "fuzz target: broken invariant: %s\n", what);
    std::abort();
}

FuzzFolder::FuzzFolder() {
    const char* tmp = std::getenv("TMPDIR");
    std::string pattern = std::string(tmp && *tmp ? tmp : "/tmp") + "/caustica-fuzz-XXXXXX";
    std::vector<char> buffer(pattern.begin(), pattern.end());
    buffer.push_back('\0');
    if (!::mkdtemp(buffer.data())) throw std::runtime_error("cannot make a folder from " + pattern);
    path_ = buffer.data();
    removed_at_exit = path_;
    std::atexit(remove_folder);
}

const FuzzFolder& FuzzFolder::get() {
    static const FuzzFolder folder;
    return folder;
}

std::string FuzzFolder::write(const std::string& name, const std::uint8_t* data, std::size_t size) const {
    const std::string file = path_ + "/" + name;
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    out.close();
    fuzz_require(static_cast<bool>(out), "the fuzz folder is writable");
    return file;
}

std::string FuzzFolder::write(const std::string& name, const std::string& text) const {
    return write(name, reinterpret_cast<const std::uint8_t*>(text.data()), text.size());
}

}  // namespace caustica::fuzz
