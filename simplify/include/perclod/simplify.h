// perclod/simplify.h - label-constrained mesh simplification and its baselines.
//
// Input: a Scene and one Label per triangle. Output: a simplified Scene with the
// same offset, component names and materials; every output triangle carries the
// component and material of the input triangle it came from.
//
// Modes (docs/method.md sections 5 and 6):
//   Fidelity the default of `perclod run`: quadric half-edge collapses of any
//            triangle, each bounded by the labels of the faces it touches.
//            A vertex takes the tightest bound of its faces (perceptible
//            e_perceptible, imperceptible e_imperceptible, undisplayable
//            e_undisplayable pixels, times p(d)) and keeps the tightest bound
//            of every vertex merged into it; a collapse is refused when its
//            error (as in Bounded) exceeds the bound of either end, or when
//            the surface area it changes, added to what the collapses merged
//            into either end changed, exceeds bound_area_px2 * max(1, e)^2 *
//            p(d)^2, e the end's bound in pixels (so the default half-pixel
//            bounds allow bound_area_px2, and looser bounds allow as much
//            more area as they allow distance squared).
//            Undisplayable triangles are deleted first, as in Paper (with
//            delete_undisplayable = false they are collapsed, unbounded). Flat
//            perceptible walls are re-tessellated (error 0); nothing moves
//            further than its label allows. Leftover pieces without a
//            perceptible face are removed when all undisplayable or when their
//            bounding-box diagonal is within e_imperceptible * p(d). With
//            free_topology (the default) the collapses go on on the plain
//            triangle list once the half-edge mesh's topological rules stop
//            them (the LOD may be non-manifold).
//   Paper    undisplayable triangles are deleted outright, then quadric
//            half-edge collapses (v0 removed, v1 kept where it is) remove
//            imperceptible triangles until none is removable, then every
//            connected piece without a perceptible triangle is removed
//            outright. With delete_undisplayable = false, the paper's own
//            rule: undisplayable triangles are collapsed like imperceptible
//            ones, and those collapses cannot reach stay.
//   Bounded  collapses of imperceptible and undisplayable triangles, but a
//            collapse whose geometric error exceeds k * pixel_footprint is
//            refused (the loop ends when none within the tolerance is left).
//            Error = sqrt of the unit-weight quadric of the kept vertex: the
//            root of the summed squared distances from v1 to every original
//            face plane (and boundary / crease constraint plane) merged into
//            it, an upper bound on its largest distance to any one of those
//            planes. Leftover pieces are removed outright when all their
//            triangles are undisplayable or their bounding-box diagonal is
//            within the tolerance. Undisplayable triangles are not deleted
//            one by one (the holes would break the bound).
//   Qem      plain Garland-Heckbert half-edge quadric simplification to
//            target_triangles; labels ignored.
//   Cluster  Rossignac-Borrel vertex clustering on a grid of cell size
//            k * pixel_footprint; labels ignored.
//
// In Paper and Bounded (not Fidelity): no vertex of a perceptible triangle moves or is removed,
// so perceptible triangles come out bit-identical (positions, and vertex order
// up to rotation). Components whose triangles are all undisplayable are
// removed before simplification. In every mode an output triangle keeps the
// winding of its input triangle, also where the collapse simplifier reversed
// it internally to join neighbours wound the other way.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "perclod/scene.h"

namespace perclod {

enum class SimplifyMode { Paper, Bounded, Qem, Cluster, Fidelity };

const char* simplify_mode_name(SimplifyMode m);
// "paper", "bounded", "qem", "cluster", "fidelity"; throws std::invalid_argument otherwise.
SimplifyMode parse_simplify_mode(const char* name);
// Paper, Bounded and Fidelity read the labels; Qem and Cluster ignore them.
bool simplify_mode_uses_labels(SimplifyMode m);
// Paper and Bounded keep perceptible triangles bit-identical.
bool simplify_mode_keeps_perceptible(SimplifyMode m);

// Fidelity's default bounds in pixels at the LOD's distance
// (BENCHMARKS.md#choosing-the-bounds gives the measurements that chose them).
constexpr double kDefaultBoundPerceptiblePx = 0.5;
constexpr double kDefaultBoundImperceptiblePx = 8;
constexpr double kDefaultBoundAreaPx2 = 1.0;

// Mesh topology the loader and scene statistics share with the simplifier.
// Corners at exactly equal positions (+0 and -0 equal) weld: the result holds
// per corner (3 per triangle) a welded vertex id, ids in order of first use.
std::vector<uint32_t> weld_exact(const Scene& scene);
// Connected parts: triangles sharing a welded vertex (weld_exact) belong to
// one part. part[t] numbers the parts in order of their first triangle;
// returns the number of parts.
uint32_t connected_parts(const Scene& scene, std::vector<uint32_t>& part);

struct SimplifyOptions {
  SimplifyMode mode = SimplifyMode::Paper;
  double pixel_footprint = 0.0;   // p(d) in scene units at the LOD's distance (Bounded, Cluster)
  double k = 1.0;                 // tolerance / cell size = k * pixel_footprint
  size_t target_triangles = 0;    // Qem: stop at this many triangles
  // Paper, Bounded, Fidelity, Qem: after the last pass, sort every half-edge
  // left by the first rule that refuses its collapse (SimplifyStats::refused):
  // why the LOD holds what it holds. One more pass over the mesh.
  bool explain_stop = false;
  // Fidelity: how far, in pixels at the distance, a collapse may move the
  // surface of a triangle of each label (infinity = unbounded).
  double bound_perceptible_px = kDefaultBoundPerceptiblePx;
  double bound_imperceptible_px = kDefaultBoundImperceptiblePx;
  double bound_undisplayable_px = INFINITY;
  // Fidelity: surface area (pixels squared at the distance) the collapses
  // merged into a vertex of a perceptible or imperceptible face may add or
  // remove in all, at bounds up to 1 px; times the bound squared above that
  // (infinity = no area rule).
  double bound_area_px2 = kDefaultBoundAreaPx2;
  // Fidelity: per input triangle, a factor on the perceptible and
  // imperceptible bounds above (and on the area budget's bound and the
  // small-piece rule) for its vertices and its piece; empty = 1 for all.
  // `run` tightens the buildings a judge finds over its limits this way,
  // leaving the others' bounds as asked.
  std::vector<float> bound_scale;
  // Fidelity: per input triangle, nonzero keeps it if undisplayable even
  // with delete_undisplayable (collapsed within bound_undisplayable_px);
  // empty = none.
  std::vector<uint8_t> keep_undisplayable_of;

  // Constraint lines (Shi, Yang, Li): edges whose dihedral angle exceeds
  // feature_angle_deg never collapse, nor move (their vertices are kept).
  bool constraint_lines = false;
  // Edges sharper than this also get crease quadrics (so they do not erode).
  double feature_angle_deg = 40.0;

  double weld_tolerance_rel = 1e-6;  // vertex welding, relative to the bbox diagonal
  // Weld only corners of the same component. Components that merely touch
  // (a frame on a wall) then stay apart instead of forming non-manifold
  // junctions whose faces would have to be isolated (bench_simplify).
  bool weld_per_component = true;
  double max_normal_change_deg = 60.0;  // refuse collapses that turn a face more
  double min_triangle_quality = 0.05;   // refuse slivers (4*sqrt3*area / sum of edge^2)
  int max_valence = 24;                 // refuse collapses that make bigger fans
  double boundary_weight = 1.0;         // weight of boundary/crease quadrics (x edge length^2)

  // Paper, Fidelity: delete undisplayable triangles instead of collapsing them (no pixel
  // centre of any labelling view reaches them, and their collapses would move
  // imperceptible triangles the views do show). false collapses them as the
  // paper does and keeps those collapses cannot reach, so closed surfaces
  // stay closed.
  bool delete_undisplayable = true;

  // Fidelity: once the half-edge collapses stop, go on collapsing on the
  // plain triangle list, where no topological rule refuses (the link
  // condition, boundary ears, pinched strips, faces on non-manifold edges):
  // only the bounds, the area rule and the shape rules. The LOD may then be
  // non-manifold. (src/free_collapse.h)
  bool free_topology = true;

  // Paper, Bounded, Fidelity: connected pieces (faces sharing a welded
  // vertex) are simplified in chunks of about this many faces, in parallel
  // (oneTBB); 0 = one chunk. Collapses never cross pieces and ties between
  // equal costs are broken by position in the input, so the output holds
  // the same triangles whatever the chunk size or thread count; only their
  // order follows the chunks (and so depends on chunk_faces alone).
  size_t chunk_faces = 16384;

  // Cluster: representative = weighted centre of mass (false: heaviest vertex).
  bool cluster_center_of_mass = true;
  // Cluster (Belblidia): cluster each component on its own and snap
  // representatives of cells touching the component's bounding box onto it.
  bool preserve_bbox = false;
};

struct SimplifyStats {
  // Triangles per label (index = Label value) before and after. Qem and
  // Cluster count with the labels given (they ignore them while simplifying).
  std::array<size_t, 3> triangles_before{0, 0, 0};
  std::array<size_t, 3> triangles_after{0, 0, 0};
  size_t vertices_before = 0;  // after welding
  size_t vertices_after = 0;
  size_t components_removed = 0;       // all-undisplayable components dropped up front
  size_t pieces_removed = 0;           // leftover connected pieces dropped after collapsing
  size_t pieces_triangles_removed = 0; // triangles in those pieces
  size_t undisplayable_faces_deleted = 0;  // Paper: undisplayable triangles deleted outright
  size_t nonmanifold_faces_duplicated = 0;  // faces added with their own vertices
  size_t degenerate_faces = 0;         // faces whose welded corners repeat (kept, duplicated)
  size_t collapses = 0;
  size_t free_collapses = 0;           // Fidelity with free_topology: of those, made on the triangle list
  size_t chunks = 0;                   // Paper, Bounded, Fidelity, Qem: chunks of pieces simplified apart (chunk_faces)
  size_t cluster_dangling_edges = 0;   // Cluster: edges bounding no kept triangle (not in the Scene)
  size_t cluster_isolated_points = 0;  // Cluster: points bounding nothing (not in the Scene)
  double tolerance = 0.0;              // Bounded: k * p(d); Cluster: cell size; Fidelity: e_imperceptible * p(d)
  double tolerance_perceptible = 0.0;  // Fidelity: e_perceptible * p(d)
  double max_error = 0.0;              // Bounded, Fidelity: largest error bound of a collapse taken (0 otherwise)
  // Qem: whether target_triangles was reached, and if not why the collapses
  // stopped (empty when reached or when the mode has no target).
  bool target_reached = true;
  std::string stop_reason;
  // Every half-edge left after the last pass, by the first rule that refuses
  // its collapse; counted when explain_stop is set or a qem target is missed
  // (refused_counted), summed over the chunks. Half-edges of pieces removed
  // afterwards are counted too.
  struct Refused {
    size_t bound_or_locked = 0;  // a fixed end, a constraint line, or over the error bound
    size_t valence = 0;          // the fan would exceed max_valence
    size_t topology = 0;         // link condition, boundary ears
    size_t shape = 0;            // normal change, sliver, area rule
    size_t legal = 0;            // became legal only after the last pass
    size_t total() const { return bound_or_locked + valence + topology + shape + legal; }
  };
  Refused refused;
  bool refused_counted = false;
  // Belblidia's measures: displacement of each input vertex to the vertex that
  // represents it in the output, relative to the bounding-box diagonal.
  double max_displacement_rel = 0.0;
  double mean_displacement_rel = 0.0;
  double bbox_diagonal = 0.0;
  double seconds = 0.0;

  size_t total_before() const { return triangles_before[0] + triangles_before[1] + triangles_before[2]; }
  size_t total_after() const { return triangles_after[0] + triangles_after[1] + triangles_after[2]; }
};

// Why a LOD stopped (SimplifyStats::refused), in words: "N half-edges left:
// X locked or over their bound, ...", as `simplify --explain` and `run`
// with explain print it.
std::string refused_text(const SimplifyStats::Refused& why);

// Simplify `scene` given one label per triangle. When `out_source` is given it
// receives, per output triangle, the index of the input triangle it came from
// (its label, component and material are that triangle's). Throws
// std::invalid_argument on bad input (label count, index out of range,
// non-finite position, missing pixel footprint for Bounded/Cluster, zero
// target for Qem).
Scene simplify(const Scene& scene, const std::vector<Label>& labels,
               const SimplifyOptions& options, SimplifyStats* stats = nullptr,
               std::vector<uint32_t>* out_source = nullptr);

}  // namespace perclod
