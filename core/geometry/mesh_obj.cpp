// Wavefront OBJ reading: our own small parser of what gr.mesh needs (v, vt, f), so that polygons of
// any size are kept whole and every bad number or index is reported with its line.
#include "core/geometry/mesh_obj.h"

#include <cerrno>
#include <cfloat>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <vector>

namespace caustica {
namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

/// Splits a line (comment removed) into white-space separated tokens.
void split_tokens(std::string_view line, std::vector<std::string_view>& tokens) {
    tokens.clear();
    if (const std::size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && is_space(line[i])) ++i;
        const std::size_t start = i;
        while (i < line.size() && !is_space(line[i])) ++i;
        if (i > start) tokens.push_back(line.substr(start, i - start));
    }
}

/// Calls `each(line_number, tokens)` for every line with at least one token.
template <typename Each>
void for_each_line(std::string_view text, Each&& each) {
    std::vector<std::string_view> tokens;
    std::size_t pos = 0;
    for (int line = 1; pos <= text.size(); ++line) {
        std::size_t end = text.find('\n', pos);
        if (end == std::string_view::npos) end = text.size();
        split_tokens(text.substr(pos, end - pos), tokens);
        pos = end + 1;
        if (!tokens.empty()) each(line, tokens);
    }
}

class ObjParser {
public:
    ObjParser(const std::string& name, const std::string& path) : name_(name), path_(path) {}

    std::shared_ptr<const MeshData> parse(std::string_view text) {
        // First the counts, so that a face index is checked where it is written (a positive index
        // may name a vertex defined further down).
        for_each_line(text, [&](int, const std::vector<std::string_view>& tokens) {
            total_vertices_ += tokens[0] == "v";
            total_texcoords_ += tokens[0] == "vt";
        });
        if (total_vertices_ > 0xffffffffu) throw InputError(name_ + ": more vertices than 32-bit indices can address");
        mesh_ = std::make_shared<MeshData>();
        mesh_->path = path_;
        mesh_->positions.reserve(total_vertices_);
        texcoords_.reserve(total_texcoords_);
        for_each_line(text, [&](int line, const std::vector<std::string_view>& tokens) {
            line_ = line;
            if (tokens[0] == "v") vertex(tokens);
            else if (tokens[0] == "vt") texcoord(tokens);
            else if (tokens[0] == "f") face(tokens);
            // Everything else (vn, o, g, s, usemtl, mtllib, l, p, ...) has no use here.
        });
        if (mesh_->triangles.empty())
            throw InputError(name_ + ": no triangles (the file has no faces with 3 or more vertices)");
        return std::move(mesh_);
    }

private:
    [[noreturn]] void fail(const std::string& message) const {
        throw InputError(name_ + ":" + std::to_string(line_) + ": " + message);
    }

    /// A coordinate: a finite number within float range.
    float coordinate(std::string_view token) const {
        if (token.size() > 1 && token.front() == '+') token.remove_prefix(1);  // from_chars takes no '+'
        double value = 0.0;
        const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
        const std::string text(token);
        if (end != token.data() + token.size() || (ec != std::errc() && ec != std::errc::result_out_of_range))
            fail("'" + text + "' is not a number");
        if (ec == std::errc::result_out_of_range) {  // beyond double: too large, or too small to matter
            if (std::strtod(text.c_str(), nullptr) != 0.0) fail("coordinate '" + text + "' is out of range");
            return 0.0f;
        }
        if (!std::isfinite(value)) fail("coordinate '" + text + "' is not a finite number");
        if (std::fabs(value) > FLT_MAX) fail("coordinate '" + text + "' is out of range");
        return static_cast<float>(value);
    }

    void vertex(const std::vector<std::string_view>& tokens) {
        if (tokens.size() < 4) fail("a vertex needs x, y and z");
        for (std::size_t i = 4; i < tokens.size(); ++i) coordinate(tokens[i]);  // w or a colour: checked, unused
        mesh_->positions.emplace_back(coordinate(tokens[1]), coordinate(tokens[2]), coordinate(tokens[3]));
    }

    void texcoord(const std::vector<std::string_view>& tokens) {
        if (tokens.size() < 2) fail("a texture coordinate needs u");
        for (std::size_t i = 3; i < tokens.size(); ++i) coordinate(tokens[i]);
        texcoords_.emplace_back(coordinate(tokens[1]), tokens.size() > 2 ? coordinate(tokens[2]) : 0.0f);
    }

    /// The 0-based item an index field names: 1..total counts from the start of the file, -1..-n
    /// back from the last item defined so far (`defined`). Any other number, however large, is
    /// out of range.
    std::size_t resolve(std::string_view field, std::size_t defined, std::size_t total, const char* what) const {
        long long value = 0;
        const auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), value);
        const bool digits = end == field.data() + field.size() && field.find_first_not_of("+-0123456789") == std::string_view::npos;
        if (!digits || (ec != std::errc() && ec != std::errc::result_out_of_range))
            fail(std::string(what) + " '" + std::string(field) + "' is not a whole number");
        const bool fits = ec == std::errc();
        if (fits && value > 0 && static_cast<unsigned long long>(value) <= total) return static_cast<std::size_t>(value - 1);
        if (fits && value < 0 && static_cast<unsigned long long>(-(value + 1)) < defined)
            return defined - 1 - static_cast<std::size_t>(-(value + 1));
        const bool negative = field.front() == '-';
        const std::string range = negative ? (defined ? "-1..-" + std::to_string(defined) : "none defined yet")
                                           : (total ? "1.." + std::to_string(total) : "the file has none");
        fail(std::string(what) + " " + std::string(field) + " is out of range (" + range + ")");
    }

    void face(const std::vector<std::string_view>& tokens) {
        for (std::size_t i = 1; i < tokens.size(); ++i) {
            const std::string_view token = tokens[i];
            const std::size_t slash = token.find('/');
            corner_vertex_.push_back(static_cast<unsigned>(
                resolve(token.substr(0, slash), mesh_->positions.size(), total_vertices_, "face index")));
            glm::vec2 uv(0.0f);
            if (slash != std::string_view::npos) {
                const std::string_view rest = token.substr(slash + 1);
                const std::string_view field = rest.substr(0, rest.find('/'));
                if (!field.empty()) {
                    uv = texcoords_[resolve(field, texcoords_.size(), total_texcoords_, "texture coordinate index")];
                    if (!has_texcoords_) {  // from now on every corner gets one; zeros for those before
                        has_texcoords_ = true;
                        mesh_->texcoords.assign(3 * mesh_->triangles.size(), glm::vec2(0.0f));
                    }
                }
            }
            corner_uv_.push_back(uv);
        }
        const std::size_t count = corner_vertex_.size();
        for (std::size_t k = 1; k + 1 < count; ++k) {  // fan around the first corner
            const std::size_t a = 0, b = k, c = k + 1;
            mesh_->triangles.emplace_back(corner_vertex_[a], corner_vertex_[b], corner_vertex_[c]);
            if (!has_texcoords_) continue;
            mesh_->texcoords.push_back(corner_uv_[a]);
            mesh_->texcoords.push_back(corner_uv_[b]);
            mesh_->texcoords.push_back(corner_uv_[c]);
        }
        corner_vertex_.clear();
        corner_uv_.clear();
    }

    std::string name_, path_;
    int line_ = 0;
    std::size_t total_vertices_ = 0, total_texcoords_ = 0;
    std::shared_ptr<MeshData> mesh_;
    std::vector<glm::vec2> texcoords_;
    bool has_texcoords_ = false;
    std::vector<unsigned> corner_vertex_;  // the corners of the face being read
    std::vector<glm::vec2> corner_uv_;
};

}  // namespace

std::shared_ptr<const MeshData> parse_obj_mesh(std::string_view text, const std::string& display_name,
                                               const std::string& source_path) {
    return ObjParser(display_name, source_path.empty() ? display_name : source_path).parse(text);
}

std::shared_ptr<const MeshData> load_obj_mesh(const std::string& path) {
    std::ifstream file(path, std::ios::binary);
    if (!file) throw InputError("cannot open '" + path + "': " + std::strerror(errno));
    const std::string text{std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
    if (file.bad()) throw InputError("cannot read '" + path + "'");
    return parse_obj_mesh(text, path);
}

}  // namespace caustica
