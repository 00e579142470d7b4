#include "gpu/gpu_passes.h"

#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "base/error.h"
#include "gpu/capabilities.h"
#include "gpu/gpu_error.h"
#include "mesh/geometry.h"

namespace vfsd::gpu {
namespace {

// Texture units of the pass inputs.
constexpr int kUnitRings = 0, kUnitNeighbours = 1, kUnitPositions = 2, kUnitNormals = 3, kUnitGradients = 4;
constexpr int kUnitExtra[3] = {5, 6, 7};  // a pass's own inputs beyond these

// s as float32, keeping its region: a value strictly inside (0, 1) in double stays
// strictly inside in float, so the GPU's 0 < s < 1 tests pick the same vertices.
float region_float(double s) {
    float f = static_cast<float>(s);
    if (s > 0.0 && f <= 0.0f) f = std::numeric_limits<float>::denorm_min();
    if (s < 1.0 && f >= 1.0f) f = std::nextafter(1.0f, 0.0f);
    return f;
}

Program fullscreen_program(const char* name, const char* fragment, bool with_field) {
    std::vector<std::string> files = {"mesh_textures.glsl"};
    if (with_field) files.push_back("field.glsl");
    files.push_back(fragment);
    return Program(name, {"fullscreen.vert"}, files);
}

// The points of `m` are taken relative to `origin`, as the textures hold positions.
void set_motion(const Program& p, const std::string& name, const MotionSample& m, const Vec3& origin) {
    auto set3 = [&](const char* field, const Vec3& v) {
        p.set((name + "." + field).c_str(), float(v.x), float(v.y), float(v.z));
    };
    set3("position", m.position - origin);
    set3("velocity", m.velocity);
    set3("angular_velocity", m.angular_velocity);
    set3("twist", m.twist);
    set3("stream_origin", m.stream_origin - origin);
    set3("twist_origin", m.twist_origin - origin);
    set3("gauge_centre", m.gauge.centre - origin);
    p.set((name + ".gauge_inverse_scale").c_str(), float(m.gauge.inverse_scale));
    for (int k = 0; k < 10; ++k)
        p.set((name + ".gauge[" + std::to_string(k) + "]").c_str(), float(m.gauge.q[0][k]), float(m.gauge.q[1][k]),
              float(m.gauge.q[2][k]));
}

}  // namespace

GpuPasses::GpuPasses(const std::vector<Vec3>& positions, const std::vector<double>& s, const VertexRings& rings)
    : count_(positions.size()) {
    if (s.size() != count_ || rings.vertex_count() != count_)
        throw InputError("GPU passes: " + std::to_string(count_) + " positions, " + std::to_string(s.size()) +
                         " values of s and rings for " + std::to_string(rings.vertex_count()) + " vertices");
    const Capabilities caps = query_capabilities();
    require_gpu_support(caps, std::max(count_, rings.neighbours.size()));
    max_texture_size_ = caps.max_texture_size;
    layout_ = TextureLayout::for_count(count_, caps.max_texture_size);
    origin_ = bounding_box(positions).centre();

    // Connectivity: ring offsets and lengths per vertex, then the ring entries.
    std::vector<std::int32_t> ring_data(layout_.texels() * 2, 0);
    for (std::uint32_t v = 0; v < count_; ++v) {
        ring_data[2 * v] = static_cast<std::int32_t>(rings.begin(v));
        ring_data[2 * v + 1] = static_cast<std::int32_t>(rings.valence(v));
    }
    const TextureLayout entries = TextureLayout::for_count(rings.neighbours.size(), caps.max_texture_size);
    std::vector<std::int32_t> entry_data(entries.texels(), 0);
    for (std::size_t i = 0; i < rings.neighbours.size(); ++i)
        entry_data[i] = static_cast<std::int32_t>((rings.neighbours[i] << 1) | (rings.wedge[i] ? 1u : 0u));
    rings_ = Texture(GL_RG32I, layout_.width, layout_.height);
    rings_.upload(ring_data.data());
    neighbours_ = Texture(GL_R32I, entries.width, entries.height);
    neighbours_.upload(entry_data.data());

    // State textures, each with its framebuffer.
    for (Target* t : {&vertex_[0], &vertex_[1], &vertex_[2], &midpoint_, &normal_, &gradient_[0], &gradient_[1]})
        *t = make_target();
    s_.resize(count_);
    for (std::size_t v = 0; v < count_; ++v) s_[v] = region_float(s[v]);
    set_positions(positions);
    set_gradients(std::vector<Vec3>(count_, Vec3(0.0)));

    normal_program_ = fullscreen_program("normal pass", "normal.frag", false);
    gradient_program_ = fullscreen_program("gradient pass", "gradient.frag", false);
    smooth_program_ = fullscreen_program("smoothing pass", "smooth.frag", false);
    deform_program_ = fullscreen_program("deformation pass", "deform.frag", true);
    check_gl("setting up the GPU passes");
}

GpuPasses::Target GpuPasses::make_target() const { return make_target(layout_.width, layout_.height); }

GpuPasses::Target GpuPasses::make_target(int width, int height) const {
    Target t;
    t.texture = Texture(GL_RGBA32F, width, height);
    t.framebuffer = Framebuffer(t.texture);
    return t;
}

const Texture& GpuPasses::source(At at) const {
    return at == At::positions ? vertex_[current_].texture : midpoint_.texture;
}

// Binds the connectivity textures and the layout uniforms of mesh_textures.glsl.
void GpuPasses::bind_mesh(const Program& program) const {
    program.use();
    program.set("u_width", layout_.width);
    program.set("u_count", static_cast<int>(count_));
    rings_.bind(kUnitRings);
    neighbours_.bind(kUnitNeighbours);
    program.set("u_rings", kUnitRings);
    program.set("u_neighbours", kUnitNeighbours);
    program.set("u_positions", kUnitPositions);
    program.set("u_normals", kUnitNormals);
    program.set("u_gradients", kUnitGradients);
}

// One fullscreen triangle into `target`: the fragment shader runs once per texel.
void GpuPasses::draw(const Target& target) const {
    target.framebuffer.bind();
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    empty_vao_.bind();
    glDrawArrays(GL_TRIANGLES, 0, 3);
}

void GpuPasses::estimate_normals(At at) {
    bind_mesh(normal_program_);
    source(at).bind(kUnitPositions);
    draw(normal_);
}

void GpuPasses::estimate_gradients(At at) {
    bind_mesh(gradient_program_);
    source(at).bind(kUnitPositions);
    normal_.texture.bind(kUnitNormals);
    draw(gradient_[current_gradient_]);
}

void GpuPasses::smooth_gradients(int steps, double weight, bool tangent) {
    bind_mesh(smooth_program_);
    smooth_program_.set("u_weight", static_cast<float>(weight));
    smooth_program_.set("u_tangent", tangent ? 1 : 0);
    vertex_[current_].texture.bind(kUnitPositions);  // only s (w) is read
    normal_.texture.bind(kUnitNormals);
    for (int step = 0; step < steps; ++step) {
        gradient_[current_gradient_].texture.bind(kUnitGradients);
        draw(gradient_[1 - current_gradient_]);
        current_gradient_ = 1 - current_gradient_;
    }
}

void GpuPasses::predict_midpoints(const StepMotion& half) { draw_deformation(half, midpoint_, true); }

void GpuPasses::deformation_step(const StepMotion& motion) {
    stage_step(motion, false);
    commit_step();
}

void GpuPasses::stage_step(const StepMotion& motion, bool keep_volume) {
    const int into = spare();
    draw_deformation(motion, vertex_[into], false);
    current_ = into;
    if (keep_volume) keep_volume_staged();
}

void GpuPasses::commit_step() { committed_ = current_; }
void GpuPasses::discard_step() { current_ = committed_; }

// The vertex texture neither the committed nor the working positions are in.
int GpuPasses::spare() const {
    for (int slot = 0;; ++slot)
        if (slot != current_ && slot != committed_) return slot;
}

// The deformation pass (deform.frag) from the current positions into `target`:
// an RK4 step, or a step of the midpoint rule (the predictor).
void GpuPasses::draw_deformation(const StepMotion& motion, const Target& target, bool midpoint_rule) const {
    bind_mesh(deform_program_);
    set_motion(deform_program_, "u_start", motion.start, origin_);
    set_motion(deform_program_, "u_middle", motion.middle, origin_);
    set_motion(deform_program_, "u_end", motion.end, origin_);
    deform_program_.set("u_h", static_cast<float>(motion.h));
    deform_program_.set("u_midpoint_rule", midpoint_rule ? 1 : 0);
    deform_program_.set("u_keep_volume", keeper_rated_ ? 1 : 0);
    deform_program_.set("u_keeper", kUnitExtra[0]);
    // Without the keeper's sums the sampler still needs a texture the pass does
    // not write: what an earlier pass left on its unit can be this pass's
    // target, and WebGL refuses that draw as a feedback loop (the page's GPU
    // path stopped at its first step with the keeper off).
    (keeper_rated_ ? keeper_sums_.back().texture : normal_.texture).bind(kUnitExtra[0]);
    vertex_[current_].texture.bind(kUnitPositions);
    gradient_[current_gradient_].texture.bind(kUnitGradients);
    normal_.texture.bind(kUnitNormals);
    draw(target);
}

// ---- Beyond the paper: the default scheme's passes ----

namespace {

// An integer texture of `count` items of `components` (1 or 4) each, laid out as
// TextureLayout::for_count lays out `count` items.
Texture integer_texture(const std::vector<std::int32_t>& items, int components, std::size_t count,
                        int max_texture_size) {
    const TextureLayout layout = TextureLayout::for_count(count, max_texture_size);
    std::vector<std::int32_t> data(layout.texels() * components, 0);
    std::copy(items.begin(), items.end(), data.begin());
    Texture t(components == 4 ? GL_RGBA32I : GL_R32I, layout.width, layout.height);
    t.upload(data.data());
    return t;
}

}  // namespace

// The targets of the sum passes that add a width x height texture up into one
// texel: each level kBlock (sum.frag) times smaller, the last 1 x 1.
std::vector<GpuPasses::Target> GpuPasses::sum_levels(int width, int height) const {
    constexpr int kBlock = 8;
    std::vector<Target> levels;
    do {
        width = (width + kBlock - 1) / kBlock, height = (height + kBlock - 1) / kBlock;
        levels.push_back(make_target(width, height));
    } while (width > 1 || height > 1);
    return levels;
}

void GpuPasses::sum(const Texture& source, const std::vector<Target>& levels) const {
    sum_program_.use();
    sum_program_.set("u_source", kUnitExtra[0]);
    const Texture* from = &source;
    for (const Target& level : levels) {
        from->bind(kUnitExtra[0]);
        sum_program_.set("u_source_size", from->width(), from->height());
        draw(level);
        from = &level.texture;
    }
}

void GpuPasses::set_gauge_samples(const std::vector<std::uint32_t>& vertices) {
    gauge_sample_count_ = vertices.size();
    if (vertices.empty()) return;
    gauge_sample_vertices_ = integer_texture(std::vector<std::int32_t>(vertices.begin(), vertices.end()), 1,
                                             vertices.size(), max_texture_size_);
    const TextureLayout layout = TextureLayout::for_count(2 * vertices.size(), max_texture_size_);
    gauge_samples_ = make_target(layout.width, layout.height);
    if (!gauge_samples_program_.id())
        gauge_samples_program_ = fullscreen_program("gauge samples", "gauge_samples.frag", false);
    check_gl("setting up the gauge samples");
}

void GpuPasses::read_gauge_samples(At at, std::vector<Vec3>& positions, std::vector<Vec3>& gradients) const {
    gather_gauge_samples(at);
    read_gathered_samples(positions, gradients);
}

void GpuPasses::gather_gauge_samples(At at) const {
    if (gauge_sample_count_ == 0) return;
    bind_mesh(gauge_samples_program_);
    gauge_samples_program_.set("u_count", static_cast<int>(2 * gauge_sample_count_));
    gauge_samples_program_.set("u_samples", kUnitExtra[0]);
    gauge_sample_vertices_.bind(kUnitExtra[0]);
    source(at).bind(kUnitPositions);
    gradient_[current_gradient_].texture.bind(kUnitGradients);
    draw(gauge_samples_);
}

void GpuPasses::read_gathered_samples(std::vector<Vec3>& positions, std::vector<Vec3>& gradients) const {
    positions.clear(), gradients.clear();
    if (gauge_sample_count_ == 0) return;
    const std::vector<float> data = gauge_samples_.framebuffer.read_rgba32f();
    for (std::size_t j = 0; j < gauge_sample_count_; ++j) {
        const float* p = &data[8 * j];
        positions.push_back(origin_ + Vec3(p[0], p[1], p[2]));
        gradients.push_back(Vec3(p[4], p[5], p[6]));
    }
}

void GpuPasses::measure_rest_volume(const Vec3& centre) {
    volume_centre_ = centre - origin_;
    volume_terms_ = make_target();
    volume_sums_ = sum_levels(layout_.width, layout_.height);
    rest_volume_sums_ = sum_levels(layout_.width, layout_.height);
    keeper_sums_ = sum_levels(layout_.width, layout_.height);
    keeper_rated_ = false;
    if (!sum_program_.id()) sum_program_ = fullscreen_program("sum pass", "sum.frag", false);
    if (!volume_program_.id()) volume_program_ = fullscreen_program("volume pass", "volume.frag", true);
    if (!keep_volume_program_.id())
        keep_volume_program_ = fullscreen_program("volume keeper pass", "keep_volume.frag", true);
    if (!keeper_rate_program_.id())
        keeper_rate_program_ = fullscreen_program("keeper rate pass", "keeper_rate.frag", true);
    sum_volume(rest_volume_sums_);
    check_gl("measuring the rest volume");
}

// The volume pass on the current positions, added up into `levels`.
void GpuPasses::sum_volume(const std::vector<Target>& levels) const {
    bind_mesh(volume_program_);
    volume_program_.set("u_centre", float(volume_centre_.x), float(volume_centre_.y), float(volume_centre_.z));
    vertex_[current_].texture.bind(kUnitPositions);
    normal_.texture.bind(kUnitNormals);
    draw(volume_terms_);
    sum(volume_terms_.texture, levels);
}

void GpuPasses::keeper_rate(At at, const MotionSample& sample) {
    if (keeper_sums_.empty()) return;
    bind_mesh(keeper_rate_program_);
    set_motion(keeper_rate_program_, "u_sample", sample, origin_);
    source(at).bind(kUnitPositions);
    normal_.texture.bind(kUnitNormals);
    gradient_[current_gradient_].texture.bind(kUnitGradients);
    draw(volume_terms_);
    sum(volume_terms_.texture, keeper_sums_);
    keeper_rated_ = true;
}

void GpuPasses::keep_volume() {
    keep_volume_staged();
    commit_step();
}

void GpuPasses::keep_volume_staged() {
    if (volume_sums_.empty()) return;
    sum_volume(volume_sums_);
    bind_mesh(keep_volume_program_);
    keep_volume_program_.set("u_volume", kUnitExtra[0]);
    keep_volume_program_.set("u_rest_volume", kUnitExtra[1]);
    volume_sums_.back().texture.bind(kUnitExtra[0]);
    rest_volume_sums_.back().texture.bind(kUnitExtra[1]);
    vertex_[current_].texture.bind(kUnitPositions);
    normal_.texture.bind(kUnitNormals);
    const int into = spare();
    draw(vertex_[into]);
    current_ = into;
}

void GpuPasses::set_fold_checks(const FoldChecks& checks, const std::vector<std::uint32_t>& to_vertex) {
    fold_check_count_ = checks.check.size();
    if (fold_check_count_ == 0) return;
    std::vector<std::int32_t> triangles, entries, neighbours(checks.neighbours.begin(), checks.neighbours.end());
    // A float's bits in an integer texel, for intBitsToFloat in the shader.
    const auto bits = [](float value) {
        std::int32_t out;
        std::memcpy(&out, &value, sizeof out);
        return out;
    };
    // Each triangle's corners, and where it is a checked one its entry's margin.
    std::vector<float> margin(checks.triangles.size(), 0.0f);
    for (std::size_t i = 0; i < fold_check_count_; ++i) margin[checks.check[i]] = checks.margin[i];
    for (std::size_t t = 0; t < checks.triangles.size(); ++t)
        for (int c = 0; c < 4; ++c)
            triangles.push_back(c < 3 ? static_cast<std::int32_t>(to_vertex[checks.triangles[t][c]]) : bits(margin[t]));
    for (std::size_t i = 0; i < fold_check_count_; ++i) {
        const std::uint32_t first = checks.neighbour_offsets[i], last = checks.neighbour_offsets[i + 1];
        for (const std::uint32_t value : {checks.check[i], first, last - first})
            entries.push_back(static_cast<std::int32_t>(value));
        entries.push_back(bits(checks.floor[i]));
    }
    fold_triangles_ = integer_texture(triangles, 4, checks.triangles.size(), max_texture_size_);
    fold_checks_ = integer_texture(entries, 4, fold_check_count_, max_texture_size_);
    fold_neighbours_ = integer_texture(neighbours, 1, neighbours.size(), max_texture_size_);
    const TextureLayout layout = TextureLayout::for_count(fold_check_count_, max_texture_size_);
    fold_flags_ = make_target(layout.width, layout.height);
    fold_sums_ = sum_levels(layout.width, layout.height);
    if (!sum_program_.id()) sum_program_ = fullscreen_program("sum pass", "sum.frag", false);
    if (!fold_program_.id()) fold_program_ = fullscreen_program("fold pass", "fold_check.frag", false);
    check_gl("setting up the fold test");
}

std::size_t GpuPasses::count_folds() const {
    test_folds();
    return read_fold_count();
}

void GpuPasses::test_folds() const {
    if (fold_check_count_ == 0) return;
    bind_mesh(fold_program_);
    fold_program_.set("u_count", static_cast<int>(fold_check_count_));
    fold_program_.set("u_fold_triangles", kUnitExtra[0]);
    fold_program_.set("u_fold_checks", kUnitExtra[1]);
    fold_program_.set("u_fold_neighbours", kUnitExtra[2]);
    fold_triangles_.bind(kUnitExtra[0]);
    fold_checks_.bind(kUnitExtra[1]);
    fold_neighbours_.bind(kUnitExtra[2]);
    vertex_[current_].texture.bind(kUnitPositions);
    draw(fold_flags_);
    sum(fold_flags_.texture, fold_sums_);
}

std::size_t GpuPasses::read_fold_count() const {
    if (fold_check_count_ == 0) return 0;
    return static_cast<std::size_t>(fold_sums_.back().framebuffer.read_rgba32f()[0] + 0.5f);
}

std::vector<float> GpuPasses::packed(const std::vector<Vec3>& xyz, bool with_s, const Vec3& origin) const {
    if (xyz.size() != count_)
        throw InputError("GPU passes: " + std::to_string(xyz.size()) + " values for " + std::to_string(count_) +
                         " vertices");
    std::vector<float> data(layout_.texels() * 4, 0.0f);
    for (std::size_t v = 0; v < count_; ++v) {
        data[4 * v] = static_cast<float>(xyz[v].x - origin.x);
        data[4 * v + 1] = static_cast<float>(xyz[v].y - origin.y);
        data[4 * v + 2] = static_cast<float>(xyz[v].z - origin.z);
        data[4 * v + 3] = with_s ? s_[v] : 0.0f;
    }
    return data;
}

void GpuPasses::set_positions(const std::vector<Vec3>& positions) {
    current_ = committed_;
    vertex_[current_].texture.upload(packed(positions, true, origin_).data());
}

void GpuPasses::set_region(const std::vector<double>& s) {
    if (s.size() != count_)
        throw InputError("GPU passes: " + std::to_string(s.size()) + " values of s for " + std::to_string(count_) +
                         " vertices");
    for (std::size_t v = 0; v < count_; ++v) s_[v] = region_float(s[v]);
}

void GpuPasses::set_gradients(const std::vector<Vec3>& gradients) {
    gradient_[current_gradient_].texture.upload(packed(gradients, false, Vec3(0.0)).data());
}

std::vector<Vec3> GpuPasses::read(const Target& target, const Vec3& origin) const {
    const std::vector<float> data = target.framebuffer.read_rgba32f();
    std::vector<Vec3> out(count_);
    for (std::size_t v = 0; v < count_; ++v) out[v] = origin + Vec3(data[4 * v], data[4 * v + 1], data[4 * v + 2]);
    return out;
}

std::vector<Vec3> GpuPasses::read_positions() const { return read(vertex_[committed_], origin_); }
std::vector<Vec3> GpuPasses::read_staged_positions() const { return read(vertex_[current_], origin_); }
std::vector<Vec3> GpuPasses::read_midpoints() const { return read(midpoint_, origin_); }
std::vector<Vec3> GpuPasses::read_normals() const { return read(normal_, Vec3(0.0)); }
std::vector<Vec3> GpuPasses::read_gradients() const { return read(gradient_[current_gradient_], Vec3(0.0)); }

}  // namespace vfsd::gpu
