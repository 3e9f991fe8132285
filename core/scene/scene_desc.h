// The plain-data scene description (IR) that the Lua loader produces and the renderer consumes.
// Nothing here knows about Lua or Embree; every entity carries the script location that made it,
// so that errors found at render time still point at the line of the scene file.
#pragma once

#include "core/scene/options.h"
#include "core/scene/source_location.h"

#include <glm/glm.hpp>

#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace caustica {

struct Png8;

/// One transform call on a node; the matrix is composed when a render resolves the convention.
struct TransformOp {
    enum class Kind { translate, scale, rotate };
    Kind kind = Kind::translate;
    glm::dvec3 amount{0.0};  ///< translation or scale factors
    int axis = 0;            ///< rotation axis: 0 = x, 1 = y, 2 = z
    double degrees = 0.0;    ///< rotation angle
    SourceLocation where;
};

/// What a node is: a transform-only group, an analytic primitive, a mesh or a CSG operation.
enum class NodeKind {
    group,  ///< gr.node and gr.joint
    sphere,
    cube,
    cylinder,
    cone,
    nh_sphere,
    nh_box,
    mesh,
    csg_union,
    csg_intersection,
    csg_difference,
};

/// Scene graph node. Children and operands are indices into SceneDesc::nodes (a DAG: reuse is
/// instancing).
struct NodeDesc {
    std::string name;
    NodeKind kind = NodeKind::group;
    SourceLocation where;
    std::vector<TransformOp> transforms;  ///< in call order
    std::vector<int> children;
    int material = -1;                    ///< index into SceneDesc::materials, -1 = inherit
    glm::dvec3 position{0.0};             ///< nh_sphere centre, nh_box corner
    double size = 1.0;                    ///< nh_sphere radius, nh_box side
    int mesh = -1;                        ///< index into SceneDesc::meshes
    int csg_left = -1, csg_right = -1;    ///< CSG operands
};

/// A texture or bump map source: an image path (absolute) or a procedural name.
struct TextureDesc {
    std::string source;       ///< absolute PNG path, or procedural name ("redcheck", "sinewaves")
    bool procedural = false;
    std::string remap;        ///< "", "cubetop", "cubefront", "cubebot", "cyltop", "conetop"
    std::shared_ptr<const Png8> image;  ///< decoded by the loader (else `source` is read at render time)
    SourceLocation where;
};

/// Phong material with the original's extensions (mirror, dielectric, air).
struct MaterialDesc {
    glm::dvec3 kd{0.0}, ks{0.0};
    double shininess = 0.0;
    bool reflective = false;             ///< m:set_reflective()
    std::optional<double> refractive_index;  ///< m:set_ri(n): transparent dielectric
    bool air = false;                    ///< gr.air(): empty medium
    int texture = -1, bumpmap = -1;      ///< indices into SceneDesc::textures
    SourceLocation where;
};

/// Point light, or spherical area light when radius > 0.
struct LightDesc {
    glm::dvec3 position{0.0}, colour{0.0};
    glm::dvec3 falloff{1.0, 0.0, 0.0};   ///< c0, c1, c2: intensity / (c0 + c1 d + c2 d^2)
    double radius = 0.0;
    SourceLocation where;
};

/// Triangle mesh as loaded from OBJ, in object space. Shared between renders and instances.
struct MeshData {
    std::string path;
    std::vector<glm::vec3> positions;
    std::vector<glm::uvec3> triangles;
    std::vector<glm::vec2> texcoords;       ///< per triangle corner (3 per triangle) or empty
};

/// Everything reachable from the scene at the moment a gr.render was called.
struct SceneDesc {
    std::vector<NodeDesc> nodes;
    std::vector<MaterialDesc> materials;
    std::vector<LightDesc> lights;
    std::vector<TextureDesc> textures;
    std::vector<std::shared_ptr<const MeshData>> meshes;
};

/// The course camera: eye point, view direction, up vector and vertical field of view.
struct CameraDesc {
    glm::dvec3 eye{0.0, 0.0, 1.0};
    glm::dvec3 view{0.0, 0.0, -1.0};
    glm::dvec3 up{0.0, 1.0, 0.0};
    double fovy_degrees = 50.0;
};

/// One gr.render call: a snapshot of the scene, the view and the options in force.
struct RenderJob {
    std::shared_ptr<const SceneDesc> scene;
    int root = -1;
    std::string output;      ///< as written in the script (relative to the working directory)
    int width = 0, height = 0;
    CameraDesc camera;
    glm::dvec3 ambient{0.0};
    std::vector<int> lights;             ///< indices into SceneDesc::lights
    glm::dvec3 miss_colour{1.0};         ///< white unless gr.set_miss_colour (docs/SCENE_LANGUAGE.md)
    Options options;                     ///< defaults + gr.option calls made before this render
    SourceLocation where;
    /// Long option names ("caustic-num-photons") with the gr.option call that set them, in call
    /// order: errors about an option's value name that line.
    std::vector<std::pair<std::string, SourceLocation>> option_origins;

    /// The gr.option call that last set `name`, or nullptr (default, command line or preset).
    const SourceLocation* option_origin(const std::string& name) const {
        for (auto it = option_origins.rbegin(); it != option_origins.rend(); ++it)
            if (it->first == name) return &it->second;
        return nullptr;
    }

    /// An error about an option's value ("--caustic-num-photons 1e11: ...") that a gr.option call
    /// set, named with that call's line; other errors as they are.
    InputError located_option_error(const InputError& error) const {
        const std::string message = error.what();
        if (message.rfind("--", 0) != 0) return error;
        const std::size_t end = message.find_first_of(" =:", 2);
        const SourceLocation* origin = option_origin(message.substr(2, end == std::string::npos ? end : end - 2));
        if (!origin) return error;
        return InputError(*origin, "gr.option: " + message);
    }

    /// Applies options given on the command line over the script's gr.option calls (the command
    /// line wins); an option it sets no longer has a script origin. `caustica render` and the
    /// preview compose their jobs through this one function, so the preview shows what render makes.
    void apply_command_line(const std::vector<std::string>& tokens) {
        std::vector<std::string> names;  // long names, whatever form the tokens took ("-j2", "-St")
        apply_option_tokens(options, tokens, nullptr, &names);
        for (const std::string& name : names)
            std::erase_if(option_origins, [&](const auto& origin) { return origin.first == name; });
    }
};

/// The result of running a scene script.
struct SceneScript {
    std::string path;
    std::vector<RenderJob> renders;
    std::vector<std::string> warnings;   ///< "file:line: message", already formatted
};

}  // namespace caustica
