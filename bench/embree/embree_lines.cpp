// embree_lines: Embree 3 yardstick for sceneinfo's global-line casting.
//
// Loads an OBJ (v / f lines only; polygons split by fan into triangles, or into
// quads with --prim quad), builds a static Embree scene (RTC_BUILD_QUALITY_HIGH),
// then casts N global lines exactly as sceneinfo samples them: two independent
// uniform points A, B on the bounding sphere (centre = bbox centre, radius = half
// the bbox diagonal), the ray from A towards B with tnear = 0, tfar = |B - A|.
//
// Modes (one per process; --mode list runs several in turn):
//   closest  one rtcIntersect1 per line (nearest hit only)
//   allhits  all hits of the line: rtcIntersect1 repeatedly, tnear moved past each
//            hit (by 2^-20 of the sphere's diameter: Embree may return a t a few ulps
//            below tnear), until no hit is left (hits come out sorted by t)
//   filter   all hits in ONE traversal: an intersection filter callback records
//            (t, patch) and rejects every hit; afterwards the hits are sorted by t and
//            deduplicated by patch (spatial splits may report a primitive twice)
//   packet8  closest hit, rtcIntersect8 on 8 independent (incoherent) lines
//   filtertally
//            filter's hits of each line (sorted, deduplicated) fed into a tally of the
//            shape of sceneinfo's global-line tally (see `Tally` below): per hit the
//            patch's leave count, per front-to-back pair of consecutive hits the packed-
//            triangle u32 count, the 64.64 continuous-information term (a log2 per pair)
//            added to both patches' sums and (n <= 1024 patches) to the pair's sum, per
//            line the I_S^c ratio sums. What "Embree as sceneinfo's caster" would cost.
//
// Hits are counted per patch (OBJ face): the 2 triangles of a quad are one patch, a
// line crossing a quad's diagonal is counted once. Lines that hit nothing count as 0.
//
// Timing: the casting loop only (line sampling + queries + hit bookkeeping), wall
// clock from the moment all threads are released until the last one finishes. Load
// and BVH build (rtcCommitScene) are reported separately.
//
// Output: one line per mode, `key=value` pairs.

#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>
#include <time.h>
#include <pmmintrin.h>
#include <xmmintrin.h>

namespace {

struct Mesh {
    std::vector<float> v;                  // xyz triples
    std::vector<double> vd;                // the same, as read (for normals and areas)
    std::vector<std::vector<uint32_t>> f;  // polygons, 0-based vertex indices
};

Mesh load_obj(const char* path) {
    std::ifstream in(path);
    if (!in) {
        std::fprintf(stderr, "cannot read %s\n", path);
        std::exit(2);
    }
    Mesh m;
    std::string line;
    while (std::getline(in, line)) {
        if (line.size() < 2) continue;
        if (line[0] == 'v' && line[1] == ' ') {
            double x, y, z;
            if (std::sscanf(line.c_str() + 2, "%lf %lf %lf", &x, &y, &z) != 3) {
                std::fprintf(stderr, "bad vertex: %s\n", line.c_str());
                std::exit(2);
            }
            m.v.push_back(float(x));
            m.v.push_back(float(y));
            m.v.push_back(float(z));
            m.vd.insert(m.vd.end(), {x, y, z});
        } else if (line[0] == 'f' && line[1] == ' ') {
            std::istringstream ss(line.substr(2));
            std::string tok;
            std::vector<uint32_t> poly;
            long nv = long(m.v.size() / 3);
            while (ss >> tok) {
                long i = std::strtol(tok.c_str(), nullptr, 10);  // "i", "i/t", "i/t/n", "i//n"
                if (i < 0) i = nv + i; else i = i - 1;
                if (i < 0 || i >= nv) {
                    std::fprintf(stderr, "bad face index: %s\n", line.c_str());
                    std::exit(2);
                }
                poly.push_back(uint32_t(i));
            }
            if (poly.size() >= 3) m.f.push_back(poly);
        }
    }
    return m;
}

// splitmix64 seeding + xoshiro256** generator; uniform doubles in [0, 1).
struct Rng {
    uint64_t s[4];
    static uint64_t splitmix(uint64_t& x) {
        uint64_t z = (x += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    Rng(uint64_t seed, uint64_t stream) {
        uint64_t x = seed * 0x100000001B3ull + stream * 0xD1B54A32D192ED03ull + 1;
        for (auto& w : s) w = splitmix(x);
    }
    static uint64_t rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
    uint64_t next() {
        uint64_t r = rotl(s[1] * 5, 7) * 9, t = s[1] << 17;
        s[2] ^= s[0]; s[3] ^= s[1]; s[1] ^= s[2]; s[0] ^= s[3]; s[2] ^= t; s[3] = rotl(s[3], 45);
        return r;
    }
    double uniform() { return double(next() >> 11) * 0x1.0p-53; }
};

struct Sphere {
    double c[3];
    double r;
};

// Uniform point of the unit sphere, as sceneinfo's sample_uniform_sphere:
// z = 1 - 2u0, rho = 2 sqrt(u0 (1 - u0)), phi = 2 pi u1.
inline void uniform_sphere(double u0, double u1, double p[3]) {
    double z = 1.0 - 2.0 * u0;
    double rho = 2.0 * std::sqrt(u0 * (1.0 - u0));
    double phi = 6.283185307179586 * u1;
    p[0] = rho * std::cos(phi);
    p[1] = rho * std::sin(phi);
    p[2] = z;
}

// A global line as a ray from A towards B (A, B uniform on the sphere); `dir_out`, if
// given, gets the unit direction in double precision (for the tally's cosines).
inline void global_ray(const Sphere& S, Rng& rng, RTCRay& ray, double* dir_out = nullptr) {
    double a[3], b[3];
    uniform_sphere(rng.uniform(), rng.uniform(), a);
    uniform_sphere(rng.uniform(), rng.uniform(), b);
    double d[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    double inv = len > 0 ? 1.0 / len : 0.0;
    if (dir_out) {
        dir_out[0] = d[0] * inv;
        dir_out[1] = d[1] * inv;
        dir_out[2] = d[2] * inv;
    }
    ray.org_x = float(S.c[0] + S.r * a[0]);
    ray.org_y = float(S.c[1] + S.r * a[1]);
    ray.org_z = float(S.c[2] + S.r * a[2]);
    ray.dir_x = float(d[0] * inv);
    ray.dir_y = float(d[1] * inv);
    ray.dir_z = float(d[2] * inv);
    ray.tnear = 0.0f;
    ray.tfar = float(len * S.r);
    ray.time = 0.0f;
    ray.mask = 0xFFFFFFFFu;
    ray.id = 0;
    ray.flags = 0;
}

double now() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double thread_cpu() {
    timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

struct Hit {
    float t;
    uint32_t patch;
};

// ---------------------------------------------------------------------------------------
// A tally of the shape of sceneinfo's global-line LineTally (core/src/tally.rs,
// core/src/tally/counts.rs, core/src/continuous.rs, core/src/math/fixed.rs and
// fast_log2.rs), written here from their documented layout and formulas so that
// "Embree + the same tally" can be timed beside sceneinfo:
//   leaves      u64 per patch: samples leaving the patch (every hit)
//   counts      u32 per unordered pair, packed lower triangle tri(i,j) = b(b+1)/2 + a
//               (a = min, b = max), wraps past 2^32 kept aside (never in these runs);
//               increments held 32 at a time and applied in a tight loop (as Pending)
//   pair info   n <= 1024 patches only: i128 (64.64 fixed point) per unordered pair,
//               the term added once (twice for i == j), held 32 at a time like the counts
//   patch info  per patch a 64.64 sum {i128, saturated flag} (32 bytes, as FixedSum)
//   continuous  per line: sum_s, sum_ss, sum_sn (64.64), sum_n, sum_nn (u128), groups
// Per line (hits sorted by t, one per patch): two hits within eps = 1e-12 r are put in
// back-then-front order (a line through a two-sided wall) or the line is degenerate and
// only counted; then each hit leaves its patch, and each pair of consecutive hits whose
// first faces along the line (cos > 0) and second back (cos < 0) is a segment: count
// C_ij, term s = log2(A_T cos_i cos_j / (pi r^2)) (4.8) quantised once, added to both
// patches' sums and the pair's; the line's sum of 2s and its sample count go to the
// ratio sums. sceneinfo also folds a line's crossings of one surface within eps into
// one (grid patches of a face); this harness folds hits by patch (filter's dedup).

const size_t DENSE_PAIR_LIMIT = 1024;  // sceneinfo keeps per-pair information up to here
const unsigned HELD = 32;              // increments held before they are applied
const double FIXED_MAX_TERM = 1.0e18;

typedef __int128 i128;
typedef unsigned __int128 u128;

// x in raw 64.64 fixed point, truncated toward zero, from the bits of x (no float ->
// integer conversion); false when x is not finite or beyond FIXED_MAX_TERM.
inline bool quantise(double x, i128& raw) {
    double a = std::fabs(x);
    if (!(a <= FIXED_MAX_TERM)) return false;
    uint64_t bits;
    std::memcpy(&bits, &a, 8);
    int biased = int(bits >> 52);
    uint64_t m = bits & ((1ull << 52) - 1);
    if (biased == 0) biased = 1; else m |= 1ull << 52;
    int shift = biased - 1011;  // a = m 2^(biased - 1075); raw = m 2^(biased - 1075 + 64)
    i128 v;
    if (shift >= 0) v = i128(m) << shift;
    else if (shift > -64) v = i128(m >> (-shift));
    else v = 0;
    raw = x < 0 ? -v : v;
    return true;
}

inline i128 sat_add(i128 a, i128 b) {
    i128 r;
    if (__builtin_add_overflow(a, b, &r)) return b > 0 ? ~(i128(1) << 127) : (i128(1) << 127);
    return r;
}

struct alignas(16) Fixed {
    i128 acc = 0;
    bool saturated = false;
    void add_raw(i128 v) {
        i128 r;
        if (__builtin_add_overflow(acc, v, &r)) {
            acc = v > 0 ? ~(i128(1) << 127) : (i128(1) << 127);
            saturated = true;
        } else {
            acc = r;
        }
    }
    void add(double x) {
        i128 v;
        if (quantise(x, v)) add_raw(v); else saturated = true;
    }
    double value() const { return double(acc) * 0x1.0p-64; }
};

// log2 x, table-driven (128 intervals of the significand, a 7-term series of ln(1+r)
// about each interval's centre, |r| <= 2^-8), as sceneinfo's per-sample logarithm.
struct Log2Table {
    double c[128], inv_c[128], log2_c[128];
    Log2Table() {
        for (int k = 0; k < 128; k++) {
            c[k] = 1.0 + (k + 0.5) / 128.0;
            inv_c[k] = 1.0 / c[k];
            log2_c[k] = double(std::log2((long double)c[k]));
        }
    }
};
const Log2Table LOG2_TABLE;

inline double log2_fast(double x) {
    if (!(x >= 2.2250738585072014e-308 && x < INFINITY)) return std::log2(x);
    uint64_t bits;
    std::memcpy(&bits, &x, 8);
    double e = double(int64_t(bits >> 52) - 1023);
    uint64_t mb = (bits & ((1ull << 52) - 1)) | (1023ull << 52);
    double m;
    std::memcpy(&m, &mb, 8);
    int k = int((bits >> 45) & 127);
    double r = (m - LOG2_TABLE.c[k]) * LOG2_TABLE.inv_c[k];
    double ln1p = r * (1.0 + r * (-0.5 + r * (1.0 / 3.0 + r * (-0.25 + r * (0.2 + r * (-1.0 / 6.0 + r * (1.0 / 7.0)))))));
    return e + (LOG2_TABLE.log2_c[k] + ln1p * 1.4426950408889634);
}

struct Patches {
    std::vector<double> normal;  // unit normals, xyz triples (fan sum of cross products)
    double total_area = 0;
    double eps = 0;              // hits closer than this along a line coincide (1e-12 r)
};

Patches patch_geometry(const Mesh& m, double radius) {
    Patches P;
    P.normal.resize(3 * m.f.size());
    for (size_t p = 0; p < m.f.size(); p++) {
        const auto& f = m.f[p];
        const double* v0 = &m.vd[3 * f[0]];
        double n[3] = {0, 0, 0};
        for (size_t k = 1; k + 1 < f.size(); k++) {
            const double* a = &m.vd[3 * f[k]];
            const double* b = &m.vd[3 * f[k + 1]];
            double u[3] = {a[0] - v0[0], a[1] - v0[1], a[2] - v0[2]};
            double w[3] = {b[0] - v0[0], b[1] - v0[1], b[2] - v0[2]};
            n[0] += u[1] * w[2] - u[2] * w[1];
            n[1] += u[2] * w[0] - u[0] * w[2];
            n[2] += u[0] * w[1] - u[1] * w[0];
        }
        double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        P.total_area += 0.5 * len;
        for (int k = 0; k < 3; k++) P.normal[3 * p + k] = len > 0 ? n[k] / len : 0.0;
    }
    P.eps = 1e-12 * radius;
    return P;
}

struct Tally {
    size_t n = 0;
    uint64_t lines = 0, segments = 0;
    std::vector<uint64_t> leaves;
    std::vector<uint32_t> counts;     // packed triangle
    std::vector<uint64_t> carries;    // wraps of counts past 2^32 (index list; never here)
    std::vector<i128> info;           // packed triangle, n <= DENSE_PAIR_LIMIT
    std::vector<Fixed> patch_info;
    Fixed sum_s, sum_ss, sum_sn;
    uint64_t sum_n = 0, groups = 0;
    u128 sum_nn = 0;
    uint32_t held[HELD];
    unsigned held_len = 0;
    uint32_t held_info_index[HELD];
    i128 held_info[HELD];
    unsigned held_info_len = 0;

    explicit Tally(size_t patches) : n(patches), leaves(patches), counts(patches * (patches + 1) / 2),
                                     patch_info(patches) {
        if (patches <= DENSE_PAIR_LIMIT) info.assign(patches * (patches + 1) / 2, 0);
    }
    static size_t tri(size_t i, size_t j) {
        size_t a = i <= j ? i : j, b = i <= j ? j : i;
        return b * (b + 1) / 2 + a;
    }
    void apply_counts() {
        for (unsigned k = 0; k < held_len; k++) {
            uint32_t& c = counts[held[k]];
            if (++c == 0) carries.push_back(held[k]);
        }
        held_len = 0;
    }
    void apply_info() {
        for (unsigned k = 0; k < held_info_len; k++) {
            i128& v = info[held_info_index[k]];
            v = sat_add(v, held_info[k]);
        }
        held_info_len = 0;
    }
    void settle() {
        apply_counts();
        apply_info();
    }
    void hold_info(size_t k, i128 raw) {
        held_info_index[held_info_len] = uint32_t(k);
        held_info[held_info_len++] = raw;
        if (held_info_len == HELD) apply_info();
    }
    // A segment between i (front) and j (back) with term s (valid or not); returns 2s.
    double pair(size_t i, size_t j, bool valid, double s) {
        segments++;
        size_t k = tri(i, j);
        held[held_len++] = uint32_t(k);
        if (held_len == HELD) apply_counts();
        if (!valid) return 0.0;
        i128 raw;
        if (!quantise(s, raw)) {
            patch_info[i].add(s);
            patch_info[j].add(s);
            return 2.0 * s;
        }
        patch_info[i].add_raw(raw);
        patch_info[j].add_raw(raw);
        if (!info.empty()) {
            hold_info(k, raw);
            if (i == j) hold_info(k, raw);
        }
        return 2.0 * s;
    }
    void end_line(double s, uint64_t samples) {
        lines++;
        groups++;
        sum_n += samples;
        sum_nn += u128(samples) * u128(samples);
        if (s == 0.0) return;
        sum_s.add(s);
        sum_ss.add(s * s);
        sum_sn.add(s * double(samples));
    }
    void merge(const Tally& o) {
        settle();
        lines += o.lines;
        segments += o.segments;
        for (size_t k = 0; k < n; k++) leaves[k] += o.leaves[k];
        for (size_t k = 0; k < counts.size(); k++) {
            uint32_t a = counts[k];
            counts[k] += o.counts[k];
            if (counts[k] < a) carries.push_back(k);
        }
        carries.insert(carries.end(), o.carries.begin(), o.carries.end());
        for (size_t k = 0; k < info.size(); k++) info[k] = sat_add(info[k], o.info[k]);
        for (size_t k = 0; k < n; k++) {
            patch_info[k].add_raw(o.patch_info[k].acc);
            patch_info[k].saturated |= o.patch_info[k].saturated;
        }
        sum_s.add_raw(o.sum_s.acc);
        sum_ss.add_raw(o.sum_ss.acc);
        sum_sn.add_raw(o.sum_sn.acc);
        sum_n += o.sum_n;
        sum_nn += o.sum_nn;
        groups += o.groups;
    }
    // I_S^c = sum_s / sum_n and its standard error (the delta method over lines).
    void estimate(double& value, double& stderr_) const {
        value = stderr_ = 0;
        if (sum_n == 0) return;
        double nn = double(sum_n);
        value = sum_s.value() / nn;
        if (groups >= 2) {
            double l = double(groups);
            double ss = sum_ss.value() - 2.0 * value * sum_sn.value() + value * value * double(sum_nn);
            stderr_ = std::sqrt(std::max(0.0, l / ((l - 1.0) * nn * nn) * ss));
        }
    }
    size_t bytes() const {
        return leaves.size() * 8 + counts.size() * 4 + info.size() * 16 + patch_info.size() * sizeof(Fixed);
    }
};

// One line's sorted, per-patch hits into the tally (see the block comment above).
inline void tally_line(Tally& T, const Patches& P, const double dir[3], Hit* hs, uint32_t h) {
    for (uint32_t a = 1; a < h; a++) {
        if (double(hs[a].t) - double(hs[a - 1].t) <= P.eps) {
            const double* na = &P.normal[3 * hs[a - 1].patch];
            const double* nb = &P.normal[3 * hs[a].patch];
            bool fa = dir[0] * na[0] + dir[1] * na[1] + dir[2] * na[2] > 0;
            bool fb = dir[0] * nb[0] + dir[1] * nb[1] + dir[2] * nb[2] > 0;
            if (fa && !fb) std::swap(hs[a - 1], hs[a]);
            else if (!(!fa && fb)) {  // two facing the same way at one point: degenerate
                T.lines++;
                return;
            }
        }
    }
    double line_sum = 0;
    double prev_cos = 0, prev_t = 0;
    uint32_t prev = UINT32_MAX;
    for (uint32_t a = 0; a < h; a++) {
        uint32_t p = hs[a].patch;
        const double* nv = &P.normal[3 * p];
        double c = dir[0] * nv[0] + dir[1] * nv[1] + dir[2] * nv[2];
        double t = double(hs[a].t);
        T.leaves[p]++;
        if (prev != UINT32_MAX && prev_cos > 0 && c < 0) {
            double r = t - prev_t;
            double f = P.total_area * prev_cos * (-c) / (3.141592653589793 * r * r);
            bool valid = f > 0 && f < INFINITY;
            line_sum += T.pair(prev, p, valid, valid ? log2_fast(f) : 0.0);
        }
        prev = p;
        prev_cos = c;
        prev_t = t;
    }
    T.end_line(line_sum, h);
}

// Context for the filter mode: RTCIntersectContext first, so the callback can cast.
struct FilterContext {
    RTCIntersectContext ctx;
    const uint32_t* prim2patch;
    Hit* hits;
    uint32_t n;
    uint32_t cap;
};

void record_and_reject(const RTCFilterFunctionNArguments* args) {
    FilterContext* fc = reinterpret_cast<FilterContext*>(args->context);
    for (unsigned i = 0; i < args->N; i++) {
        if (args->valid[i] == 0) continue;
        if (fc->n < fc->cap) {
            fc->hits[fc->n].t = RTCRayN_tfar(args->ray, args->N, i);
            fc->hits[fc->n].patch = fc->prim2patch[RTCHitN_primID(args->hit, args->N, i)];
            fc->n++;
        }
        args->valid[i] = 0;  // reject: traversal goes on, tfar is restored
    }
}

struct Built {
    RTCScene scene;
    std::vector<uint32_t> prim2patch;
    size_t prims;
};

Built build(RTCDevice dev, const Mesh& m, bool quads, bool filter) {
    Built b;
    b.scene = rtcNewScene(dev);
    rtcSetSceneBuildQuality(b.scene, RTC_BUILD_QUALITY_HIGH);
    rtcSetSceneFlags(b.scene, RTC_SCENE_FLAG_NONE);
    RTCGeometry g = rtcNewGeometry(dev, quads ? RTC_GEOMETRY_TYPE_QUAD : RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetGeometryBuildQuality(g, RTC_BUILD_QUALITY_HIGH);
    size_t nv = m.v.size() / 3;
    float* vb = (float*)rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                3 * sizeof(float), nv);
    std::memcpy(vb, m.v.data(), m.v.size() * sizeof(float));
    std::vector<uint32_t> idx;
    for (size_t p = 0; p < m.f.size(); p++) {
        const auto& f = m.f[p];
        if (!quads) {
            for (size_t k = 1; k + 1 < f.size(); k++) {
                idx.insert(idx.end(), {f[0], f[k], f[k + 1]});
                b.prim2patch.push_back(uint32_t(p));
            }
        } else {
            // fan of quads (v0, vk, vk+1, vk+2); a lone triangle as (v0, vk, vk+1, vk+1)
            size_t k = 1;
            for (; k + 2 < f.size(); k += 2) {
                idx.insert(idx.end(), {f[0], f[k], f[k + 1], f[k + 2]});
                b.prim2patch.push_back(uint32_t(p));
            }
            if (k + 1 < f.size()) {
                idx.insert(idx.end(), {f[0], f[k], f[k + 1], f[k + 1]});
                b.prim2patch.push_back(uint32_t(p));
            }
        }
    }
    unsigned per = quads ? 4 : 3;
    b.prims = idx.size() / per;
    uint32_t* ib = (uint32_t*)rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_INDEX, 0, quads ? RTC_FORMAT_UINT4 : RTC_FORMAT_UINT3, per * sizeof(uint32_t), b.prims);
    std::memcpy(ib, idx.data(), idx.size() * sizeof(uint32_t));
    if (filter) rtcSetGeometryIntersectFilterFunction(g, record_and_reject);
    rtcCommitGeometry(g);
    rtcAttachGeometry(b.scene, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(b.scene);
    return b;
}

struct Result {
    uint64_t repeats = 0;     // allhits: the same patch returned again (not counted)
    uint64_t capped = 0;      // allhits: lines that hit MAX_STEPS
    uint64_t lines = 0;
    uint64_t hits = 0;        // hits counted per patch (all-hits modes) or lines hit (closest)
    uint64_t max_hits = 0;
    double cpu = 0;
};

const unsigned MAX_HITS = 4096;   // filter mode: hit buffer per line
const unsigned MAX_STEPS = 4096;  // allhits mode: rtcIntersect1 calls per line at most
// allhits mode: tnear steps this fraction of the sphere's diameter past each hit
// (2^-20: about 8 float ulps at the far end of a chord).
const double ALLHITS_EPS = 0x1.0p-20;

void run_closest(RTCScene scene, const Sphere& S, uint64_t seed, unsigned tid, uint64_t n, Result& r) {
    Rng rng(seed, tid);
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh;
    uint64_t hit = 0;
    for (uint64_t i = 0; i < n; i++) {
        global_ray(S, rng, rh.ray);
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene, &ctx, &rh);
        hit += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
    }
    r.lines = n;
    r.hits = hit;
    r.max_hits = 1;
}

void run_packet8(RTCScene scene, const Sphere& S, uint64_t seed, unsigned tid, uint64_t n, Result& r) {
    Rng rng(seed, tid);
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    alignas(32) RTCRayHit8 rh;
    alignas(32) int valid[8];
    uint64_t hit = 0, done = 0;
    while (done < n) {
        unsigned m = unsigned(std::min<uint64_t>(8, n - done));
        for (unsigned j = 0; j < 8; j++) {
            RTCRay ray;
            global_ray(S, rng, ray);
            valid[j] = j < m ? -1 : 0;
            rh.ray.org_x[j] = ray.org_x; rh.ray.org_y[j] = ray.org_y; rh.ray.org_z[j] = ray.org_z;
            rh.ray.dir_x[j] = ray.dir_x; rh.ray.dir_y[j] = ray.dir_y; rh.ray.dir_z[j] = ray.dir_z;
            rh.ray.tnear[j] = 0.0f; rh.ray.tfar[j] = ray.tfar; rh.ray.time[j] = 0.0f;
            rh.ray.mask[j] = 0xFFFFFFFFu; rh.ray.id[j] = j; rh.ray.flags[j] = 0;
            rh.hit.geomID[j] = RTC_INVALID_GEOMETRY_ID;
            rh.hit.instID[0][j] = RTC_INVALID_GEOMETRY_ID;
        }
        rtcIntersect8(valid, scene, &ctx, &rh);
        for (unsigned j = 0; j < m; j++) hit += rh.hit.geomID[j] != RTC_INVALID_GEOMETRY_ID;
        done += m;
    }
    r.lines = n;
    r.hits = hit;
    r.max_hits = 1;
}

void run_allhits(RTCScene scene, const uint32_t* p2p, const Sphere& S, uint64_t seed, unsigned tid, uint64_t n,
                 Result& r) {
    Rng rng(seed, tid);
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh;
    uint64_t hits = 0, maxh = 0, repeats = 0, capped = 0;
    const float eps = float(ALLHITS_EPS * 2.0 * S.r);
    for (uint64_t i = 0; i < n; i++) {
        global_ray(S, rng, rh.ray);
        const float len = rh.ray.tfar;
        uint32_t last = UINT32_MAX;
        uint64_t h = 0;
        for (unsigned it = 0; it < MAX_STEPS; it++) {
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(scene, &ctx, &rh);
            if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) break;
            uint32_t p = p2p[rh.hit.primID];
            if (p != last) {  // a quad's two triangles on its diagonal: one patch, one hit
                h++;
                last = p;
            } else {
                repeats++;
            }
            // Embree tests tnear before its final division, so the t it returns may lie a
            // few ulps BELOW tnear (the same hit again): step past max(t, tnear) by eps.
            rh.ray.tnear = std::max(rh.ray.tfar, rh.ray.tnear) + eps;
            rh.ray.tfar = len;
            if (it + 1 == MAX_STEPS) capped++;
        }
        hits += h;
        maxh = std::max(maxh, h);
    }
    r.lines = n;
    r.hits = hits;
    r.max_hits = maxh;
    r.repeats = repeats;
    r.capped = capped;
}

// Sorts a line's recorded hits by t (insertion sort: a handful of hits), then drops
// repeats of a patch; returns how many are left (at the front of hs).
inline uint32_t sort_dedup(Hit* hs, uint32_t k) {
    for (uint32_t a = 1; a < k; a++) {
        Hit x = hs[a];
        uint32_t b = a;
        while (b > 0 && hs[b - 1].t > x.t) {
            hs[b] = hs[b - 1];
            b--;
        }
        hs[b] = x;
    }
    uint32_t h = 0;
    for (uint32_t a = 0; a < k; a++) {
        bool seen = false;
        for (uint32_t c = 0; c < h; c++) seen |= hs[c].patch == hs[a].patch;
        if (!seen) hs[h++] = hs[a];
    }
    return h;
}

void run_filter(RTCScene scene, const uint32_t* p2p, const Sphere& S, uint64_t seed, unsigned tid, uint64_t n,
                Result& r) {
    Rng rng(seed, tid);
    std::vector<Hit> buf(MAX_HITS);
    FilterContext fc;
    rtcInitIntersectContext(&fc.ctx);
    fc.prim2patch = p2p;
    fc.hits = buf.data();
    fc.cap = MAX_HITS;
    RTCRayHit rh;
    uint64_t hits = 0, maxh = 0;
    for (uint64_t i = 0; i < n; i++) {
        global_ray(S, rng, rh.ray);
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        fc.n = 0;
        rtcIntersect1(scene, &fc.ctx, &rh);
        uint64_t h = sort_dedup(fc.hits, fc.n);
        hits += h;
        maxh = std::max(maxh, h);
    }
    r.lines = n;
    r.hits = hits;
    r.max_hits = maxh;
}

// filter, each line's hits then tallied as sceneinfo tallies a global line (Tally).
void run_filter_tally(RTCScene scene, const uint32_t* p2p, const Patches& P, const Sphere& S, uint64_t seed,
                      unsigned tid, uint64_t n, Result& r, Tally& T) {
    Rng rng(seed, tid);
    std::vector<Hit> buf(MAX_HITS);
    FilterContext fc;
    rtcInitIntersectContext(&fc.ctx);
    fc.prim2patch = p2p;
    fc.hits = buf.data();
    fc.cap = MAX_HITS;
    RTCRayHit rh;
    double dir[3];
    uint64_t hits = 0, maxh = 0;
    for (uint64_t i = 0; i < n; i++) {
        global_ray(S, rng, rh.ray, dir);
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        fc.n = 0;
        rtcIntersect1(scene, &fc.ctx, &rh);
        uint32_t h = sort_dedup(fc.hits, fc.n);
        tally_line(T, P, dir, fc.hits, h);
        hits += h;
        maxh = std::max<uint64_t>(maxh, h);
    }
    T.settle();
    r.lines = n;
    r.hits = hits;
    r.max_hits = maxh;
}

void usage() {
    std::fprintf(stderr,
                 "usage: embree_lines FILE.obj [--lines N] [--threads T] [--mode closest|allhits|filter|filtertally|packet8[,..]]\n"
                 "                    [--seed S] [--prim tri|quad] [--verbose]\n");
    std::exit(2);
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) usage();
    const char* file = argv[1];
    uint64_t lines = 10000000;
    unsigned threads = 1;
    uint64_t seed = 1;
    std::string modes = "closest";
    bool quads = false, verbose = false;
    for (int i = 2; i < argc; i++) {
        std::string a = argv[i];
        auto val = [&]() -> std::string {
            if (i + 1 >= argc) usage();
            return argv[++i];
        };
        if (a == "--lines") lines = uint64_t(std::strtod(val().c_str(), nullptr));
        else if (a == "--threads") threads = unsigned(std::atoi(val().c_str()));
        else if (a == "--seed") seed = std::strtoull(val().c_str(), nullptr, 10);
        else if (a == "--mode") modes = val();
        else if (a == "--prim") quads = val() == "quad";
        else if (a == "--verbose") verbose = true;
        else usage();
    }
    if (threads < 1) threads = 1;

    double t0 = now();
    Mesh m = load_obj(file);
    double t_load = now() - t0;
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    // bounds of the vertices the faces use (sceneinfo's scene bounds)
    for (const auto& f : m.f)
        for (uint32_t vi : f)
            for (int k = 0; k < 3; k++) {
                lo[k] = std::min(lo[k], m.v[3 * vi + k]);
                hi[k] = std::max(hi[k], m.v[3 * vi + k]);
            }
    Sphere S;
    double d2 = 0;
    for (int k = 0; k < 3; k++) {
        S.c[k] = 0.5 * double(lo[k]) + 0.5 * double(hi[k]);
        double e = double(hi[k]) - double(lo[k]);
        d2 += e * e;
    }
    S.r = 0.5 * std::sqrt(d2) * (1.0 + 1e-9);

    RTCDevice dev = rtcNewDevice(verbose ? "verbose=1" : nullptr);
    if (!dev) {
        std::fprintf(stderr, "rtcNewDevice failed: %d\n", int(rtcGetDeviceError(nullptr)));
        return 1;
    }

    std::stringstream ms(modes);
    std::string mode;
    while (std::getline(ms, mode, ',')) {
        if (mode != "closest" && mode != "allhits" && mode != "filter" && mode != "filtertally" &&
            mode != "packet8")
            usage();
        bool filter = mode == "filter" || mode == "filtertally";
        bool tallied = mode == "filtertally";
        double tb = now();
        Built b = build(dev, m, quads, filter);
        double t_build = now() - tb;
        if (rtcGetDeviceError(dev) != RTC_ERROR_NONE) {
            std::fprintf(stderr, "embree error %d\n", int(rtcGetDeviceError(dev)));
            return 1;
        }
        std::vector<Result> res(threads);
        // One tally per thread, allocated and zeroed (its pages touched) before the clock
        // starts, as sceneinfo's marginal rate leaves out allocating its tallies.
        std::vector<std::unique_ptr<Tally>> tallies;
        Patches P;
        if (tallied) {
            P = patch_geometry(m, S.r);
            for (unsigned t = 0; t < threads; t++) tallies.emplace_back(new Tally(m.f.size()));
        }
        std::vector<std::thread> pool;
        std::atomic<unsigned> ready{0};
        std::atomic<bool> go{false};
        double start = 0;
        for (unsigned t = 0; t < threads; t++) {
            uint64_t n = lines / threads + (t < lines % threads ? 1 : 0);
            pool.emplace_back([&, t, n]() {
                // as Embree asks of every thread that traces (no denormals here anyway)
                _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
                _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
                ready++;
                while (!go.load(std::memory_order_acquire)) std::this_thread::yield();
                double c0 = thread_cpu();
                if (mode == "closest") run_closest(b.scene, S, seed, t, n, res[t]);
                else if (mode == "packet8") run_packet8(b.scene, S, seed, t, n, res[t]);
                else if (mode == "allhits") run_allhits(b.scene, b.prim2patch.data(), S, seed, t, n, res[t]);
                else if (tallied)
                    run_filter_tally(b.scene, b.prim2patch.data(), P, S, seed, t, n, res[t], *tallies[t]);
                else run_filter(b.scene, b.prim2patch.data(), S, seed, t, n, res[t]);
                res[t].cpu = thread_cpu() - c0;
            });
        }
        while (ready.load() < threads) std::this_thread::yield();
        start = now();
        go.store(true, std::memory_order_release);
        for (auto& th : pool) th.join();
        double wall = now() - start;
        // The tallies merged after the clock (a per-job cost, as in sceneinfo's marginal
        // rate), for the estimate and checks printed.
        std::string tally_keys;
        if (tallied) {
            double tm = now();
            for (unsigned t = 1; t < threads; t++) tallies[0]->merge(*tallies[t]);
            double merge_s = now() - tm;
            const Tally& T = *tallies[0];
            double isc, isc_se;
            T.estimate(isc, isc_se);
            uint64_t leaves = 0;
            for (uint64_t l : T.leaves) leaves += l;
            char kv[512];
            std::snprintf(kv, sizeof kv,
                          " merge_s=%.4f tally_mb=%.1f pair_info=%d isc=%.9f isc_stderr=%.3g samples=%llu "
                          "segments=%llu tally_lines=%llu",
                          merge_s, double(T.bytes()) / 1e6, int(!T.info.empty()), isc, isc_se,
                          (unsigned long long)leaves, (unsigned long long)T.segments,
                          (unsigned long long)T.lines);
            tally_keys = kv;
        }
        Result tot;
        double cpu = 0;
        for (auto& r : res) {
            tot.lines += r.lines;
            tot.hits += r.hits;
            tot.max_hits = std::max(tot.max_hits, r.max_hits);
            tot.repeats += r.repeats;
            tot.capped += r.capped;
            cpu += r.cpu;
        }
        bool closest = mode == "closest" || mode == "packet8";
        std::printf(
            "embree=%s mode=%s prim=%s threads=%u patches=%zu prims=%zu lines=%llu load_s=%.4f build_s=%.4f "
            "cast_s=%.4f cpu_s=%.4f lines_per_s=%.1f %s=%.6f max_hits=%llu repeats=%llu capped=%llu%s\n",
            RTC_VERSION_STRING, mode.c_str(), quads ? "quad" : "tri", threads, m.f.size(), b.prims,
            (unsigned long long)tot.lines, t_load, t_build, wall, cpu, double(tot.lines) / wall,
            closest ? "hit_fraction" : "hits_per_line", double(tot.hits) / double(tot.lines),
            (unsigned long long)tot.max_hits, (unsigned long long)tot.repeats, (unsigned long long)tot.capped,
            tally_keys.c_str());
        std::fflush(stdout);
        rtcReleaseScene(b.scene);
    }
    rtcReleaseDevice(dev);
    return 0;
}
