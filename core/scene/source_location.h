// Script locations and the error type that carries them.
#pragma once

#include <stdexcept>
#include <string>

namespace caustica {

/// Where in a scene script something was made: "file.lua:12".
struct SourceLocation {
    std::string file;
    int line = 0;

    /// "file:line", or "" when unknown.
    std::string str() const { return file.empty() ? std::string() : file + ":" + std::to_string(line); }
};

/// A problem with the user's input (scene, option, file): reported as is, exit code 2.
class InputError : public std::runtime_error {
public:
    explicit InputError(const std::string& message) : std::runtime_error(message) {}
    /// Prefixes the message with "file:line: " when the location is known.
    InputError(const SourceLocation& where, const std::string& message)
        : std::runtime_error(where.file.empty() ? message : where.str() + ": " + message) {}
};

}  // namespace caustica
