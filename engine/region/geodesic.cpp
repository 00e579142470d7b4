// Approximate geodesic distances: shortest-path propagation plus local smoothing
// (sec. 6.1 of von Funck, Theisel, Seidel, "Explicit Control of Vector Field Based
// Shape Deformations").
// References: Dijkstra (1959); Kimmel & Sethian, "Computing geodesic paths on
// manifolds" (1998) for fast marching on triangles; the point-source triangle update
// follows Novotni & Klein, "Computing geodesic distances on triangular meshes" (2002).
#include "region/geodesic.h"

#include <cmath>
#include <functional>
#include <queue>
#include <string>

#include "base/error.h"

namespace vfsd {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct HeapEntry {
    double distance;
    std::uint32_t vertex;
    bool operator>(const HeapEntry& o) const { return distance > o.distance; }
};
using MinHeap = std::priority_queue<HeapEntry, std::vector<HeapEntry>, std::greater<HeapEntry>>;

// A weighted graph in CSR form: the links of vertex v are [offsets[v], offsets[v+1]).
struct LinkGraph {
    std::vector<std::uint32_t> offsets;
    std::vector<std::uint32_t> targets;
    std::vector<double> lengths;
};

// The other apex w of the triangle across edge (a, b) from the triangle (v, a, b):
// in a's ring that triangle is (a, w, b), so w precedes b. Returns false if absent.
bool opposite_apex(const VertexRings& rings, std::uint32_t a, std::uint32_t b, std::uint32_t& w) {
    for (std::uint32_t i = rings.begin(a); i < rings.end(a); ++i) {
        if (rings.neighbours[i] != b) continue;
        const std::uint32_t prev = i == rings.begin(a) ? rings.end(a) - 1 : i - 1;
        if (!rings.wedge[prev]) return false;
        w = rings.neighbours[prev];
        return true;
    }
    return false;
}

// Length of the straight link v-w across edge (a, b) in the unfolded pair of triangles
// (v, a, b) and (w, b, a); +infinity when the unfolded segment misses the edge (the
// quad is not convex there, so the shortest path runs through a or b anyway).
double unfolded_link_length(const Vec3& v, const Vec3& w, const Vec3& a, const Vec3& b) {
    const Vec3 e = b - a;
    const double len = glm::length(e);
    if (len <= 0.0) return kInf;
    const Vec3 u = e / len;
    const double xv = glm::dot(v - a, u), yv = glm::length((v - a) - xv * u);
    const double xw = glm::dot(w - a, u), yw = glm::length((w - a) - xw * u);
    if (yv + yw <= 0.0) return kInf;
    const double x = xv + (xw - xv) * yv / (yv + yw);  // where the segment meets the edge line
    if (x <= 0.0 || x >= len) return kInf;
    return std::hypot(xv - xw, yv + yw);
}

// The edge graph of the rings, optionally with the edge-flip links added.
LinkGraph build_link_graph(const std::vector<Vec3>& p, const VertexRings& rings, bool flip_links) {
    const auto n = static_cast<std::uint32_t>(rings.vertex_count());
    LinkGraph g;
    g.offsets.assign(n + 1, 0);
    g.targets.reserve(rings.neighbours.size() * (flip_links ? 2 : 1));
    g.lengths.reserve(g.targets.capacity());
    for (std::uint32_t v = 0; v < n; ++v) {
        for (std::uint32_t i = rings.begin(v); i < rings.end(v); ++i) {
            const std::uint32_t a = rings.neighbours[i];
            g.targets.push_back(a);
            g.lengths.push_back(glm::length(p[a] - p[v]));
            std::uint32_t w = 0;
            const std::uint32_t b = rings.neighbours[rings.next(v, i)];
            if (!flip_links || !rings.wedge[i] || !opposite_apex(rings, a, b, w) || w == v) continue;
            const double len = unfolded_link_length(p[v], p[w], p[a], p[b]);
            if (len < kInf) {
                g.targets.push_back(w);
                g.lengths.push_back(len);
            }
        }
        g.offsets[v + 1] = static_cast<std::uint32_t>(g.targets.size());
    }
    return g;
}

void push_seeds(const std::vector<double>& dist, MinHeap& heap) {
    for (std::uint32_t v = 0; v < dist.size(); ++v)
        if (dist[v] < kInf) heap.push({dist[v], v});
}

void run_dijkstra(const LinkGraph& g, double max_distance, std::vector<double>& dist) {
    MinHeap heap;
    push_seeds(dist, heap);
    while (!heap.empty()) {
        const HeapEntry top = heap.top();
        heap.pop();
        if (top.distance > dist[top.vertex] || top.distance > max_distance) continue;  // stale or too far
        for (std::uint32_t i = g.offsets[top.vertex]; i < g.offsets[top.vertex + 1]; ++i) {
            const double d = top.distance + g.lengths[i];
            if (d < dist[g.targets[i]]) {
                dist[g.targets[i]] = d;
                heap.push({d, g.targets[i]});
            }
        }
    }
}

// Distance at c from the known corners a, b of a triangle: unfold a virtual point
// source s with |s-a| = da, |s-b| = db on the far side of edge ab; valid when the ray
// s -> c crosses the edge and the result is causal (larger than da and db).
double triangle_update(const Vec3& c, const Vec3& a, double da, const Vec3& b, double db) {
    const Vec3 e = b - a;
    const double len = glm::length(e);
    if (len <= 0.0) return kInf;
    const Vec3 u = e / len;
    const double cx = glm::dot(c - a, u), cy = glm::length((c - a) - cx * u);
    const double sx = (da * da - db * db + len * len) / (2.0 * len);
    // The checks below meet their limits exactly on regular meshes (a source on
    // the edge's line, a ray through a corner, c level with a known corner), where
    // the update equals the edge update or a known distance; a tolerance keeps
    // rounding from choosing, so that the same mesh turned or moved gets the same
    // distances.
    const double tolerance = 1e-9;
    const double sy2 = da * da - sx * sx;
    if (sy2 < -tolerance * len * len || cy <= 0.0) return kInf;
    const double sy = -std::sqrt(std::max(sy2, 0.0));
    const double x = sx + (cx - sx) * (-sy) / (cy - sy);  // the ray meets the edge line here
    if (x < -tolerance * len || x > (1.0 + tolerance) * len) return kInf;
    const double d = std::hypot(cx - sx, cy - sy), known = std::max(da, db);
    return d >= known - tolerance * len ? std::max(d, known) : kInf;
}

// Fast marching fixes each vertex from the neighbours accepted before it, so the
// order of acceptance shapes the result. Where two fronts arrive together (ties,
// common on regular meshes) plain distance order leaves it to rounding error, and
// the same mesh turned or mirrored would get other distances. Here distances
// within a quantum (1e-9 of the mean edge length) count as equal and the lower
// vertex index goes first: an order that does not depend on where the mesh lies.
struct MarchKey {
    double quantised;  // distance / quantum, rounded down
    std::uint32_t vertex;
    bool operator<(const MarchKey& o) const {
        return quantised != o.quantised ? quantised < o.quantised : vertex < o.vertex;
    }
};

// The march's front: a binary min-heap of MarchKeys holding each vertex at most
// once, its key lowered in place when its distance falls (a heap that pushed
// each lowered distance again held several entries per vertex, most of them
// stale). Vertices leave it in the same order: each has one live key.
class MarchFront {
public:
    explicit MarchFront(std::size_t vertex_count) : slot_(vertex_count, kAbsent) {}
    bool empty() const { return heap_.empty(); }
    // Adds v with this key, or lowers v's key to it.
    void lower(const MarchKey& key) {
        std::uint32_t i = slot_[key.vertex];
        if (i == kAbsent) {
            i = static_cast<std::uint32_t>(heap_.size());
            heap_.push_back(key);
        } else {
            heap_[i] = key;
        }
        rise(i);
    }
    MarchKey pop() {
        const MarchKey top = heap_.front();
        slot_[top.vertex] = kAbsent;
        const MarchKey last = heap_.back();
        heap_.pop_back();
        if (!heap_.empty()) {
            heap_.front() = last;
            sink(0);
        }
        return top;
    }

private:
    static constexpr std::uint32_t kAbsent = 0xffffffffu;
    void place(std::uint32_t i, const MarchKey& key) { heap_[i] = key, slot_[key.vertex] = i; }
    void rise(std::uint32_t i) {
        const MarchKey key = heap_[i];
        while (i > 0) {
            const std::uint32_t parent = (i - 1) / 2;
            if (!(key < heap_[parent])) break;
            place(i, heap_[parent]);
            i = parent;
        }
        place(i, key);
    }
    void sink(std::uint32_t i) {
        const MarchKey key = heap_[i];
        const auto n = static_cast<std::uint32_t>(heap_.size());
        for (;;) {
            std::uint32_t child = 2 * i + 1;
            if (child >= n) break;
            if (child + 1 < n && heap_[child + 1] < heap_[child]) ++child;
            if (!(heap_[child] < key)) break;
            place(i, heap_[child]);
            i = child;
        }
        place(i, key);
    }
    std::vector<MarchKey> heap_;
    std::vector<std::uint32_t> slot_;  // per vertex: its place in heap_, or kAbsent
};

double mean_edge_length(const std::vector<Vec3>& p, const VertexRings& rings) {
    double sum = 0.0;
    for (std::uint32_t v = 0; v < rings.vertex_count(); ++v)
        for (std::uint32_t i = rings.begin(v); i < rings.end(v); ++i) sum += glm::length(p[rings.neighbours[i]] - p[v]);
    return rings.neighbours.empty() ? 0.0 : sum / double(rings.neighbours.size());
}

void run_fast_marching(const std::vector<Vec3>& p, const VertexRings& rings, double max_distance,
                       std::vector<double>& dist) {
    const double quantum = 1e-9 * mean_edge_length(p, rings);
    const auto key = [&](double d, std::uint32_t v) {
        return MarchKey{quantum > 0.0 ? std::floor(d / quantum) : d, v};
    };
    std::vector<std::uint8_t> accepted(dist.size(), 0);
    MarchFront front(dist.size());
    for (std::uint32_t v = 0; v < dist.size(); ++v)
        if (dist[v] < kInf) {
            // A source inside a region of sources (itself and its whole ring at 0)
            // updates no vertex and no update reaches it: accepted at once, it
            // stays out of the front (a painted region's thousands of vertices).
            bool inside = dist[v] == 0.0 && rings.valence(v) > 0;
            for (std::uint32_t i = rings.begin(v); i < rings.end(v) && inside; ++i)
                inside = dist[rings.neighbours[i]] == 0.0;
            if (inside)
                accepted[v] = 1;
            else
                front.lower(key(dist[v], v));
        }
    const auto relax = [&](std::uint32_t v, double d) {
        if (d < dist[v]) {
            dist[v] = d;
            front.lower(key(d, v));
        }
    };
    while (!front.empty()) {
        const std::uint32_t v = front.pop().vertex;
        if (dist[v] > max_distance) continue;  // left out; a shorter update may bring it back
        accepted[v] = 1;
        for (std::uint32_t i = rings.begin(v); i < rings.end(v); ++i) {
            const std::uint32_t a = rings.neighbours[i];
            if (!accepted[a]) relax(a, dist[v] + glm::length(p[a] - p[v]));  // edge update
            if (!rings.wedge[i]) continue;
            // Triangle (v, a, b): update the one corner not yet accepted from the other two.
            const std::uint32_t b = rings.neighbours[rings.next(v, i)];
            if (!accepted[a] && accepted[b]) relax(a, triangle_update(p[a], p[v], dist[v], p[b], dist[b]));
            if (!accepted[b] && accepted[a]) relax(b, triangle_update(p[b], p[v], dist[v], p[a], dist[a]));
        }
    }
}

// True when ring entry i of v is a boundary edge: no triangle on one of its sides.
bool is_boundary_entry(const VertexRings& rings, std::uint32_t v, std::uint32_t i) {
    const std::uint32_t prev = i == rings.begin(v) ? rings.end(v) - 1 : i - 1;
    return !rings.wedge[i] || !rings.wedge[prev];
}

// True when v has exactly two boundary edges and they continue each other within
// about 25 degrees. Corners and non-manifold boundary vertices are not smoothed:
// averaging around a corner would pull the value towards the inside.
bool is_straight_boundary(const std::vector<Vec3>& p, const VertexRings& rings, std::uint32_t v) {
    Vec3 dir[2];
    int count = 0;
    for (std::uint32_t i = rings.begin(v); i < rings.end(v); ++i) {
        if (!is_boundary_entry(rings, v, i)) continue;
        if (count == 2) return false;
        dir[count++] = glm::normalize(p[rings.neighbours[i]] - p[v]);
    }
    return count == 2 && glm::dot(dir[0], dir[1]) < -0.9;
}

// The local smoothing kernel of sec. 6.1: Jacobi passes of
//   g(v) <- 1/2 g(v) + 1/2 (sum_w g(w) / |vw|) / (sum_w 1 / |vw|)
// over the 1-ring, skipping seeded vertices and unreached (+infinity) values. A vertex
// on the mesh boundary averages over its two boundary edges only (a one-sided 1-ring
// would shift its value by up to half an edge length); boundary corners keep theirs.
void smooth_distances(const std::vector<Vec3>& p, const VertexRings& rings, const std::vector<double>& seeds,
                      int iterations, std::vector<double>& dist) {
    if (iterations == 0) return;
    // The vertices the kernel moves (reached, not seeded, not a boundary corner)
    // and, per ring entry of each, the length of its edge where the kernel weighs
    // it, else 0, and its weight 1 / length: taken once for all passes. A march
    // stopped at max_distance reaches part of the mesh, and only that part is visited.
    std::vector<std::uint32_t> smoothed, offsets{0};
    std::vector<double> length, inverse;
    for (std::uint32_t v = 0; v < dist.size(); ++v) {
        if (seeds[v] < kInf || dist[v] == kInf) continue;
        const bool boundary = !rings.is_closed(v);
        if (boundary && !is_straight_boundary(p, rings, v)) continue;
        smoothed.push_back(v);
        for (std::uint32_t i = rings.begin(v); i < rings.end(v); ++i)
            length.push_back(!boundary || is_boundary_entry(rings, v, i) ? glm::length(p[rings.neighbours[i]] - p[v])
                                                                         : 0.0);
        offsets.push_back(static_cast<std::uint32_t>(length.size()));
    }
    inverse.reserve(length.size());
    for (const double len : length) inverse.push_back(len > 0.0 ? 1.0 / len : 0.0);
    std::vector<double> next = dist;
    for (int it = 0; it < iterations; ++it) {
        for (std::size_t j = 0; j < smoothed.size(); ++j) {
            const std::uint32_t v = smoothed[j];
            double sum = 0.0, weight = 0.0;
            for (std::uint32_t i = rings.begin(v), k = offsets[j]; i < rings.end(v); ++i, ++k) {
                const std::uint32_t w = rings.neighbours[i];
                const double len = length[k];
                if (dist[w] == kInf || len <= 0.0) continue;
                sum += dist[w] / len;
                weight += inverse[k];
            }
            next[v] = weight > 0.0 ? 0.5 * dist[v] + 0.5 * sum / weight : dist[v];
        }
        dist.swap(next);
    }
}

}  // namespace

std::vector<double> geodesic_distance_from_seeds(const std::vector<Vec3>& positions, const VertexRings& rings,
                                                 const std::vector<double>& seeds, const GeodesicOptions& options) {
    if (rings.vertex_count() != positions.size() || seeds.size() != positions.size())
        throw InputError("geodesic distance: positions, rings and seeds disagree on the vertex count");
    for (double s : seeds)
        if (std::isnan(s) || s < 0.0 || s == -kInf)
            throw InputError("geodesic distance: seed distances must be >= 0 or +infinity");
    if (options.smoothing_iterations < 0)
        throw InputError("geodesic distance: smoothing_iterations must be >= 0");
    std::vector<double> dist = seeds;
    if (options.method == GeodesicMethod::fast_marching) {
        run_fast_marching(positions, rings, options.max_distance, dist);
    } else {
        const bool flips = options.method == GeodesicMethod::dijkstra_flip_links;
        run_dijkstra(build_link_graph(positions, rings, flips), options.max_distance, dist);
    }
    // Values pushed but never settled beyond max_distance are left out.
    for (double& d : dist)
        if (d > options.max_distance) d = kInf;
    smooth_distances(positions, rings, seeds, options.smoothing_iterations, dist);
    return dist;
}

std::vector<double> geodesic_distance(const std::vector<Vec3>& positions, const VertexRings& rings,
                                      const std::vector<std::uint32_t>& sources, const GeodesicOptions& options) {
    std::vector<double> seeds(positions.size(), kInf);
    for (std::uint32_t v : sources) {
        if (v >= seeds.size())
            throw InputError("geodesic distance: source vertex " + std::to_string(v) + " out of range (mesh has " +
                             std::to_string(seeds.size()) + " vertices)");
        seeds[v] = 0.0;
    }
    return geodesic_distance_from_seeds(positions, rings, seeds, options);
}

std::vector<double> geodesic_distance_to_region(const std::vector<Vec3>& positions, const VertexRings& rings,
                                                const std::vector<std::uint8_t>& region,
                                                const GeodesicOptions& options) {
    if (region.size() != positions.size())
        throw InputError("geodesic distance: the region mask has " + std::to_string(region.size()) +
                         " entries, the mesh " + std::to_string(positions.size()) + " vertices");
    // Every region vertex is a source; only its border vertices have neighbours outside,
    // so the distances grow from the border.
    std::vector<double> seeds(positions.size(), kInf);
    for (std::size_t v = 0; v < region.size(); ++v)
        if (region[v]) seeds[v] = 0.0;
    return geodesic_distance_from_seeds(positions, rings, seeds, options);
}

std::vector<double> geodesic_distance_from_point(const std::vector<Vec3>& positions,
                                                 const std::vector<Triangle>& triangles,
                                                 const VertexRings& rings, const SurfacePoint& point,
                                                 const GeodesicOptions& options) {
    check_surface_point(point, triangles.size(), "geodesic source point");
    const Vec3 x = surface_position(positions, triangles, point);
    std::vector<double> seeds(positions.size(), kInf);
    for (int k = 0; k < 3; ++k) {
        const std::uint32_t v = triangles[point.triangle][k];
        if (v >= seeds.size()) throw InputError("geodesic source point: triangle refers to a missing vertex");
        seeds[v] = glm::length(positions[v] - x);
    }
    return geodesic_distance_from_seeds(positions, rings, seeds, options);
}

}  // namespace vfsd
