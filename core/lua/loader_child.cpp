#include "core/lua/loader_child.h"

#include "core/lua/lua_context.h"
#include "core/lua/scene_wire.h"
#include "core/util/printable_text.h"
#include "core/util/sanitized.h"

#include <signal.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <new>
#include <type_traits>

namespace caustica::scene_lua {
namespace {

constexpr std::uint32_t request_magic = 0x43534c52u;  // "CSLR"

static_assert(std::is_trivially_copyable_v<Options>);

template <class T>
void put(std::string& out, const T& value) {
    out.append(reinterpret_cast<const char*>(&value), sizeof value);
}

void put_text(std::string& out, const std::string& text) {
    put(out, static_cast<std::uint64_t>(text.size()));
    out += text;
}

/// Reads the request; false when it is damaged.
class RequestReader {
public:
    explicit RequestReader(std::string_view bytes) : bytes_(bytes) {}
    template <class T>
    bool get(T& value) {
        if (bytes_.size() - at_ < sizeof value) return false;
        std::memcpy(&value, bytes_.data() + at_, sizeof value);
        at_ += sizeof value;
        return true;
    }
    bool get_text(std::string& text) {
        std::uint64_t size = 0;
        if (!get(size) || size > bytes_.size() - at_) return false;
        text.assign(bytes_.data() + at_, static_cast<std::size_t>(size));
        at_ += static_cast<std::size_t>(size);
        return true;
    }

private:
    std::string_view bytes_;
    std::size_t at_ = 0;
};

void on_stop_request(int) { stop_requested = 1; }

#ifndef CAUSTICA_SANITIZED
/// What the process may use besides the script's budget (the interpreter, the C++ heap, the reply).
constexpr std::size_t address_space_slack = std::size_t(512) << 20;

/// VmData of this process in bytes (0 when /proc cannot say).
std::size_t data_segment_bytes() {
    std::ifstream status("/proc/self/status");
    std::string key;
    while (status >> key) {
        if (key == "VmData:") {
            std::size_t kib = 0;
            status >> kib;
            return kib << 10;
        }
        status.ignore(1 << 16, '\n');
    }
    return 0;
}
#endif

std::string read_all(int fd) {
    std::string bytes;
    char buffer[1 << 14];
    for (;;) {
        const ssize_t got = ::read(fd, buffer, sizeof buffer);
        if (got < 0 && errno == EINTR) continue;
        if (got <= 0) return bytes;
        bytes.append(buffer, static_cast<std::size_t>(got));
    }
}

std::string run(const std::string& request) {
    RequestReader r(request);
    std::uint32_t magic = 0;
    std::string path;
    LoadSettings settings;
    std::uint8_t output_given = 0;
    std::uint64_t memory = 0, folders = 0;
    if (!r.get(magic) || magic != request_magic || !r.get_text(path) || !r.get(settings.base_options) ||
        !r.get(settings.timeout_seconds) || !r.get(memory) || !r.get(output_given) || !r.get(folders))
        return "Xthe scene loader's request is damaged";
    settings.memory_limit_bytes = static_cast<std::size_t>(memory);
    settings.output_given = output_given != 0;
    for (std::uint64_t i = 0; i < folders; ++i)
        if (!r.get_text(settings.allow_read.emplace_back())) return "Xthe scene loader's request is damaged";

#ifndef CAUSTICA_SANITIZED  // sanitizers reserve far more address space than they use
    if (settings.memory_limit_bytes != 0) {
        if (const std::size_t base = data_segment_bytes(); base != 0) {
            const rlim_t cap = base + settings.memory_limit_bytes + settings.memory_limit_bytes / 4 + address_space_slack;
            const rlimit data{cap, cap};
            ::setrlimit(RLIMIT_DATA, &data);
        }
    }
#endif
    void* page = ::mmap(nullptr, sizeof(SharedProgress), PROT_READ | PROT_WRITE, MAP_SHARED, progress_fd, 0);
    SharedProgress* progress = page == MAP_FAILED ? nullptr : static_cast<SharedProgress*>(page);
    try {
        try {
            std::string reply = "O";  // not "O" + string: GCC 12 warns (-Wrestrict) on that inlined insert
            reply += encode_scene_script(run_script(path, settings, progress));
            return reply;
        } catch (const ScriptCancelled&) {
            return "C";
        } catch (const InputError& e) {
            return "E" + printable_text(e.what());
        } catch (const std::bad_alloc&) {
            return "Mout of memory";
        } catch (const std::exception& e) {
            return "X" + printable_text(e.what());
        }
    } catch (...) {
        return "Mout of memory";
    }
}

}  // namespace

bool write_all(int fd, const char* data, std::size_t size) {
    while (size) {
        const ssize_t done = ::write(fd, data, size);
        if (done < 0 && errno == EINTR) continue;
        if (done <= 0) return false;
        data += done;
        size -= static_cast<std::size_t>(done);
    }
    return true;
}

std::string encode_load_request(const std::string& path, const LoadSettings& settings) {
    std::string out;
    put(out, request_magic);
    put_text(out, path);
    put(out, settings.base_options);
    put(out, settings.timeout_seconds);
    put(out, static_cast<std::uint64_t>(settings.memory_limit_bytes));
    put(out, static_cast<std::uint8_t>(settings.output_given));
    put(out, static_cast<std::uint64_t>(settings.allow_read.size()));
    for (const std::string& folder : settings.allow_read) put_text(out, folder);
    return out;
}

int run_loader_child() {
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);  // never outlive the caller
    ::signal(SIGINT, SIG_IGN);           // the caller stops the loader on Ctrl-C
    ::signal(SIGUSR1, on_stop_request);  // the caller's stop request (scene_process.cpp)
    const rlimit no_core{0, 0};
    ::setrlimit(RLIMIT_CORE, &no_core);
    const std::string request = read_all(request_fd);
    ::close(request_fd);
    std::string reply;
    try {
        reply = run(request);
    } catch (...) {
        reply = "Mout of memory";
    }
    std::fflush(stdout);
    std::fflush(stderr);
    const std::uint64_t size = reply.size();
    const bool sent = write_all(reply_fd, reinterpret_cast<const char*>(&size), sizeof size) &&
                      write_all(reply_fd, reply.data(), reply.size());
    return sent ? 0 : 1;
}

}  // namespace caustica::scene_lua
