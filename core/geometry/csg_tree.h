// A CSG object ready to trace: the flattened tree of operations over leaf primitives (analytic
// shapes, or closed meshes traced through their own Embree scene), each internal node with its
// world bounding box. Evaluated along a ray it gives the interval list of csg_intervals.h.
#pragma once

#include "core/geometry/csg_intervals.h"
#include "core/scene/scene_desc.h"
#include "core/scene/scene_flatten.h"
#include "core/geometry/shapes.h"

#include <embree3/rtcore.h>
#include <glm/glm.hpp>

#include <atomic>
#include <functional>
#include <vector>

namespace caustica {

/// A leaf primitive of a CSG tree in the world.
struct CsgLeaf {
    bool is_mesh = false;
    Shape shape;                         ///< when !is_mesh
    const MeshData* mesh = nullptr;      ///< when is_mesh (closed, counter-clockwise = outward)
    RTCScene mesh_scene = nullptr;       ///< the mesh's own BVH in object space (owned elsewhere)
    float mesh_step = 0.0f;              ///< object-space distance between repeated mesh queries
    glm::mat4 world_to_object{1.0f};
    glm::mat3 object_to_world{1.0f};     ///< linear part, for tangents
    glm::mat3 normal_to_world{1.0f};
    int material = 0;                    ///< resolved material index (never -1)
    bool transparent = false;            ///< the material is transparent (set_ri, or air)
    glm::vec3 lo{0.0f}, hi{0.0f};        ///< world bounds
};

/// World box of the 8 corners of an object box under `m`, padded by a relative margin so that
/// float rounding in ray tests never falls outside it.
void transformed_box(const glm::vec3& lo, const glm::vec3& hi, const glm::mat4& m, glm::vec3& out_lo,
                     glm::vec3& out_hi);

/// The segments of a line inside a closed mesh placed by `leaf`, found by repeated nearest-hit
/// queries through its Embree scene; crossings are entering or leaving by the sign of
/// dot(outward normal, direction). `box_in`..`box_out` is where the line is in the leaf's box.
void mesh_leaf_segments(const CsgLeaf& leaf, int leaf_index, const glm::vec3& o, const glm::vec3& d, float box_in,
                        float box_out, CsgSegmentList& out);

/// One CSG object. Immutable once built (apart from the two settings below, changed only while
/// no ray is traced); evaluation uses only the caller's stack.
class CsgTree {
public:
    /// Builds the tree. `mesh_scene(i)` gives the Embree scene of SceneDesc mesh `i`;
    /// `default_material` replaces a missing material.
    CsgTree(const FlatCsgObject& object, const SceneDesc& desc, int default_material,
            const std::function<RTCScene(int)>& mesh_scene);

    /// The interval list of the whole line o + t d (t may be negative). With bounding boxes on,
    /// subtrees (leaves included) whose box the line misses within [tnear, tfar] (padded by
    /// 2 epsilon) are left out: the list is then exact inside that range only. Every leaf reads
    /// `cancel` (null: none) first and is empty once it is set: the list is then meaningless, and
    /// the walk that remains only combines empty lists (docs/RELIABILITY.md, "Bounded time").
    void evaluate(const glm::vec3& o, const glm::vec3& d, float tnear, float tfar, CsgSegmentList& out,
                  const std::atomic<bool>* cancel = nullptr) const;

    /// The first boundary of the solid in [tnear, tfar]; `list` receives the interval list
    /// (`out.surface` points into it). A surface carved by a difference's second operand B with a
    /// transparent material has B's material as its inside medium: the path that re-enters the
    /// solid there is tinted by B (docs/SCENE_LANGUAGE.md, "CSG media").
    /// `cancel` as for evaluate().
    bool first_boundary(const glm::vec3& o, const glm::vec3& d, float tnear, float tfar, CsgSegmentList& list,
                        CsgBoundary& out, const std::atomic<bool>* cancel = nullptr) const;

    /// Sets the distance below which CSG treats surfaces as touching (relative to the scene).
    void set_epsilon(float epsilon) { epsilon_ = epsilon; }
    /// Turns the bounding-box tests of internal nodes on or off (--disable-csg-bb).
    void set_bounding_boxes(bool on) { use_boxes_ = on; }

    /// A leaf primitive (CsgCrossing::leaf indexes these).
    const CsgLeaf& leaf(int index) const { return leaves_[static_cast<std::size_t>(index)]; }
    /// How many leaf primitives the object has.
    std::size_t leaf_count() const { return leaves_.size(); }
    /// World bounds of the root (empty when lo > hi: the object can never be hit).
    glm::vec3 lo() const { return nodes_[root_].lo; }
    glm::vec3 hi() const { return nodes_[root_].hi; }
    /// Whether the root box is empty (e.g. an intersection of disjoint boxes).
    bool empty() const;
    /// The CSG node of the scene description that made the object.
    int source_node() const { return source_node_; }

private:
    struct Node {
        FlatCsgNode::Kind kind = FlatCsgNode::Kind::leaf;
        int left = -1, right = -1, leaf = -1;
        glm::vec3 lo{0.0f}, hi{0.0f};
        bool empty_box = false;  // lo > hi on some axis: never hit
    };
    /// The precomputed ray of one evaluation.
    struct LineQuery {
        glm::vec3 o, d, inv_d;
        float range_lo, range_hi;  // box tests only look for overlap with this range of t
        const std::atomic<bool>* cancel;  // the render's cancel flag, or null
    };

    /// Builds the tree nodes of the flat tree under `flat_root` (iteratively); returns the root.
    int build(const FlatCsgObject& object, int flat_root);
    /// Makes the tree node of one flat node whose operands are already built.
    int finish_node(const FlatCsgObject& object, int flat_index, const std::vector<int>& operands);
    /// Which operands of an operation node the line can meet.
    enum class Plan { nothing, left_only, right_only, both };
    /// Whether the line meets the node's box within the query's range (always, with boxes off).
    bool worth_visiting(int index, const LineQuery& q) const;
    Plan plan(const Node& node, const LineQuery& q) const;
    /// The operation of `node` applied to its operands' lists.
    void combine(const Node& node, const CsgSegmentList& left, const CsgSegmentList& right, CsgSegmentList& out) const;
    /// The node's list; its own box has already been tested by the caller. Recursive up to a
    /// small depth, then evaluate_deep.
    void evaluate_node(int index, const LineQuery& q, CsgSegmentList& out, int depth) const;
    /// The same walk with an explicit stack: any depth.
    void evaluate_deep(int index, const LineQuery& q, CsgSegmentList& out) const;
    void leaf_segments(int leaf_index, const LineQuery& q, CsgSegmentList& out) const;

    std::vector<Node> nodes_;
    std::vector<CsgLeaf> leaves_;
    int root_ = 0;
    int source_node_ = -1;
    float epsilon_ = 0.0f;
    bool use_boxes_ = true;
};

}  // namespace caustica
