#include "mesh/triangle_bvh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <glm/common.hpp>

#include "base/parallel.h"

namespace vfsd {

namespace {
constexpr float kInf = std::numeric_limits<float>::infinity();
}  // namespace

// A box in float for building. glm::min / glm::max keep the first argument when
// the second is NaN, so a non-finite vertex never spreads over a box.
struct BvhBox {
    glm::vec3 lo{kInf}, hi{-kInf};
    void add(const glm::vec3& p) { lo = glm::min(lo, p), hi = glm::max(hi, p); }
    void add(const BvhBox& b) { lo = glm::min(lo, b.lo), hi = glm::max(hi, b.hi); }
    glm::vec3 centre() const { return 0.5f * (lo + hi); }
    float half_area() const {
        const glm::vec3 e = glm::max(hi - lo, glm::vec3(0.0f));
        return e.x * e.y + e.y * e.z + e.z * e.x;
    }
};

namespace {

constexpr std::uint32_t kLeafSize = 4;  // at most this many triangles in a leaf
constexpr int kBins = 16;               // split candidates
constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
// Box tests grow every box by this fraction of the scene's and the ray origin's
// size: far more than the boxes' rounding to float (6e-8 of a coordinate) and the
// ray–triangle test's rounding (about 2e-7 of the distance from origin to
// triangle, nearly parallel rays being misses: mesh/ray_cast.cpp).
constexpr double kSlack = 1e-5;

std::vector<BvhBox> triangle_boxes(const std::vector<Vec3>& positions, const std::vector<Triangle>& triangles) {
    std::vector<BvhBox> boxes(triangles.size());
    for (std::size_t i = 0; i < triangles.size(); ++i)
        for (int k = 0; k < 3; ++k) boxes[i].add(glm::vec3(positions[triangles[i][k]]));
    return boxes;
}

// Which of the kBins bins along `axis` a centroid falls in (0 for NaN).
struct Binning {
    int axis = 0;
    float lo = 0.0f, per_unit = 0.0f;
    int bin(const BvhBox& box) const {
        const float f = (box.centre()[axis] - lo) * per_unit;
        return f > 0.0f ? int(std::min(f, float(kBins - 1))) : 0;
    }
};

struct Split {
    Binning binning;
    int last_left_bin = -1;  // bins 0..last_left_bin go left; -1: no split found
    float cost = kInf;
};

// The best split along the binning's axis by the surface area heuristic: the least
// left area × left count + right area × right count over the bin boundaries.
void consider_axis(const std::vector<BvhBox>& boxes, const std::uint32_t* begin, const std::uint32_t* end,
                   const Binning& binning, Split& best) {
    std::array<BvhBox, kBins> bin_box;
    std::array<std::uint32_t, kBins> bin_count{};
    for (const std::uint32_t* i = begin; i != end; ++i) {
        const int b = binning.bin(boxes[*i]);
        bin_box[b].add(boxes[*i]);
        ++bin_count[b];
    }
    std::array<float, kBins> right_cost{};  // of bins k.. together
    BvhBox right;
    std::uint32_t right_count = 0;
    for (int k = kBins - 1; k > 0; --k) {
        right.add(bin_box[k]), right_count += bin_count[k];
        right_cost[k] = right.half_area() * float(right_count);
    }
    BvhBox left;
    std::uint32_t left_count = 0;
    for (int k = 0; k + 1 < kBins; ++k) {
        left.add(bin_box[k]), left_count += bin_count[k];
        if (left_count == 0 || left_count == static_cast<std::uint32_t>(end - begin)) continue;
        const float cost = left.half_area() * float(left_count) + right_cost[k + 1];
        if (cost < best.cost) best = {binning, k, cost};
    }
}

// Reorders [begin, end) into the two children; returns where the second starts.
std::uint32_t* split(const std::vector<BvhBox>& boxes, std::uint32_t* begin, std::uint32_t* end) {
    BvhBox centroids;
    for (const std::uint32_t* i = begin; i != end; ++i) centroids.add(boxes[*i].centre());
    Split best;
    const glm::vec3 extents = centroids.hi - centroids.lo;
    const int axis = extents.x >= extents.y && extents.x >= extents.z ? 0 : extents.y >= extents.z ? 1 : 2;
    const float extent = extents[axis];
    if (extent > 0.0f && extent < kInf)
        consider_axis(boxes, begin, end, {axis, centroids.lo[axis], float(kBins) / extent}, best);
    // All centroids in one place (or in one bin): any halves are as good.
    if (best.last_left_bin < 0) return begin + (end - begin) / 2;
    return std::partition(begin, end, [&](std::uint32_t i) { return best.binning.bin(boxes[i]) <= best.last_left_bin; });
}

// A ray made ready for box tests: the part of it inside a box grown by `slack`.
class RaySlabs {
public:
    RaySlabs(const Ray& ray, double slack) : origin_(ray.origin), direction_(ray.direction), slack_(slack) {
        for (int axis = 0; axis < 3; ++axis) inverse_[axis] = 1.0 / direction_[axis];
    }

    // Where the ray enters the box, if it passes through it between t = 0 and t_max.
    // NaN in a bound skips that test rather than the box.
    std::optional<double> enters(const glm::vec3& lo, const glm::vec3& hi, double t_max) const {
        double near = -std::numeric_limits<double>::infinity(), far = std::numeric_limits<double>::infinity();
        for (int axis = 0; axis < 3; ++axis) {
            const double a = double(lo[axis]) - slack_ - origin_[axis], b = double(hi[axis]) + slack_ - origin_[axis];
            if (direction_[axis] == 0.0) {
                if (a > 0.0 || b < 0.0) return std::nullopt;  // beside the slab, running along it
                continue;
            }
            const double ta = a * inverse_[axis], tb = b * inverse_[axis];
            near = std::max(near, std::min(ta, tb)), far = std::min(far, std::max(ta, tb));
        }
        if (near > far || far < 0.0 || near > t_max) return std::nullopt;
        return near;
    }

private:
    Vec3 origin_, direction_, inverse_;
    double slack_;
};

double largest_coordinate(const Vec3& p) { return std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}); }

}  // namespace

TriangleBvh::TriangleBvh(const std::vector<Vec3>& positions, const std::vector<Triangle>& triangles) {
    std::vector<std::uint32_t> order(triangles.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<std::uint32_t>(i);
    if (!order.empty()) build_nodes(triangle_boxes(positions, triangles), order);
    triangles_.reserve(order.size());
    for (std::uint32_t i : order) triangles_.push_back(triangles[i]);
    mesh_triangle_ = std::move(order);
    refit(positions);
}

void TriangleBvh::build_nodes(const std::vector<BvhBox>& boxes, std::vector<std::uint32_t>& order) {
    // Depth first without recursion: a node's first child is made right after it;
    // the second child's task remembers the parent that must point to it.
    struct Task {
        std::uint32_t begin, end, parent;  // parent: kNone unless this is a second child
        std::size_t depth;
    };
    std::vector<Task> tasks{{0, static_cast<std::uint32_t>(order.size()), kNone, 1}};
    while (!tasks.empty()) {
        const Task task = tasks.back();
        tasks.pop_back();
        const auto index = static_cast<std::uint32_t>(nodes_.size());
        if (task.parent != kNone) nodes_[task.parent].first = index;
        nodes_.push_back({glm::vec3(0.0f), glm::vec3(0.0f), task.begin, task.end - task.begin});
        depth_ = std::max(depth_, task.depth);
        if (task.end - task.begin <= kLeafSize) continue;
        const auto middle = static_cast<std::uint32_t>(split(boxes, &order[task.begin], &order[0] + task.end) - &order[0]);
        nodes_[index].count = 0;
        tasks.push_back({middle, task.end, index, task.depth + 1});
        tasks.push_back({task.begin, middle, kNone, task.depth + 1});
    }
}

void TriangleBvh::refit(const std::vector<Vec3>& positions) {
    // The leaves in parallel; then the inner nodes backwards, since children
    // follow their parents and so are done first.
    parallel_for(nodes_.size(), [&](std::size_t begin, std::size_t end) {
        for (std::size_t k = begin; k < end; ++k)
            if (nodes_[k].count > 0) fit_leaf(nodes_[k], positions);
    });
    for (std::size_t k = nodes_.size(); k-- > 0;) {
        Node& node = nodes_[k];
        if (node.count > 0) continue;
        const Node &a = nodes_[k + 1], &b = nodes_[node.first];
        node.lo = glm::min(a.lo, b.lo), node.hi = glm::max(a.hi, b.hi);
    }
    scale_ = 0.0;
    if (!nodes_.empty())
        for (int axis = 0; axis < 3; ++axis)
            scale_ = std::max({scale_, std::abs(double(nodes_[0].lo[axis])), std::abs(double(nodes_[0].hi[axis]))});
}

void TriangleBvh::fit_leaf(Node& leaf, const std::vector<Vec3>& positions) const {
    Vec3 lo(std::numeric_limits<double>::infinity()), hi(-lo);
    for (std::uint32_t i = leaf.first; i < leaf.first + leaf.count; ++i)
        for (int k = 0; k < 3; ++k) {
            const Vec3& p = positions[triangles_[i][k]];
            lo = glm::min(lo, p), hi = glm::max(hi, p);
        }
    leaf.lo = glm::vec3(lo), leaf.hi = glm::vec3(hi);
}

std::optional<RayHit> TriangleBvh::first_hit(const Ray& ray, const std::vector<Vec3>& positions) const {
    // Depth first, the nearer child first; a box entered beyond the best hit so far
    // is skipped (not one entered at the same distance: a lower index may wait there).
    std::optional<RayHit> best;
    const RaySlabs slabs(ray, kSlack * (scale_ + largest_coordinate(ray.origin)));
    const auto reach = [&] { return best ? best->t : std::numeric_limits<double>::infinity(); };
    std::vector<std::pair<std::uint32_t, double>> waiting;  // nodes and where the ray enters them
    waiting.reserve(depth_);
    if (nodes_.empty() || !slabs.enters(nodes_[0].lo, nodes_[0].hi, reach())) return best;
    for (std::uint32_t index = 0;;) {
        const Node& node = nodes_[index];
        if (node.count > 0) {
            for (std::uint32_t i = node.first; i < node.first + node.count; ++i) {
                const Triangle& tri = triangles_[i];
                keep_first(best, intersect_triangle(ray, positions[tri[0]], positions[tri[1]], positions[tri[2]],
                                                    mesh_triangle_[i]));
            }
        } else {
            const std::uint32_t a = index + 1, b = node.first;
            const auto enter_a = slabs.enters(nodes_[a].lo, nodes_[a].hi, reach());
            const auto enter_b = slabs.enters(nodes_[b].lo, nodes_[b].hi, reach());
            if (enter_a && enter_b) {
                const bool a_first = *enter_a <= *enter_b;
                waiting.emplace_back(a_first ? b : a, a_first ? *enter_b : *enter_a);
                index = a_first ? a : b;
                continue;
            }
            if (enter_a || enter_b) {
                index = enter_a ? a : b;
                continue;
            }
        }
        // The next waiting node the ray still reaches, if any.
        while (!waiting.empty() && waiting.back().second > reach()) waiting.pop_back();
        if (waiting.empty()) return best;
        index = waiting.back().first;
        waiting.pop_back();
    }
}

}  // namespace vfsd
