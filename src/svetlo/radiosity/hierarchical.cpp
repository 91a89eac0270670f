// Hierarchical radiosity (Hanrahan, Salzman and Aupperle, "A Rapid Hierarchical Radiosity
// Algorithm", SIGGRAPH 1991), on the element tree's quadtrees (solver.h):
//
//   1. every ordered pair of roots (the scene's triangles) that face each other is refined:
//      while the oracle's estimate of the light a link would carry, rho_r F_rs B_s, exceeds
//      link_epsilon times the brightest emitter's radiosity, the larger node is split (down
//      to element_size / 2^max_subdivision) and its children are linked instead;
//   2. a sweep gathers along every link (E_r += F_rs B_s), pushes each node's gathered
//      irradiance down to the leaves, and pulls radiosity up as area means;
//   3. sweeps run until the change falls below the tolerance; the links are then refined again
//      with the new radiosities (BF refinement), until no link splits.
//
// The roots are linked pairwise, so the scene's triangles must be few (kMaxHierarchicalRoots):
// clustering, which would lift that limit, is not built (docs/radiosity.md).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "svetlo/core/error.h"
#include "svetlo/core/parallel.h"
#include "svetlo/radiosity/solver.h"

namespace svetlo {

namespace {

struct Link {
    uint32_t receiver, source;
    float F[2] = {-1.0f, 0.0f};  // receiver's front and back side to source (form_factors.h)
};

class Hierarchy {
public:
    explicit Hierarchy(SolverInput& in) : in_(in), tree_(in.tree) {}

    Solution solve() {
        Solution sol;
        grow_arrays();
        light_for_new_leaves();
        // The brightest emitter's radiosity scales the oracle's threshold.
        float b_max = 0.0f;
        for (size_t id = 0; id < tree_.nodes().size(); ++id) {
            b_max = std::max(b_max, channel_sum(tree_.node(static_cast<uint32_t>(id)).emission));
            b_max = std::max(b_max, channel_sum(light_[id].v[0]));
            b_max = std::max(b_max, channel_sum(light_[id].v[1]));
        }
        threshold_ = in_.settings.link_epsilon * b_max;
        initial_radiosity();

        // 1. Link the roots, refining by the first estimate of B.
        const uint32_t roots = static_cast<uint32_t>(tree_.root_count());
        for (uint32_t r = 0; r < roots; ++r) {
            for (uint32_t s = 0; s < roots; ++s) {
                pending_ = static_cast<size_t>(roots - r - 1) * roots + (roots - s - 1);
                if (r != s && facing(r, s)) refine(r, s);
            }
        }
        pending_ = 0;
        finish_new_links();

        double power = 0.0;
        for (uint32_t id = 0; id < tree_.nodes().size(); ++id) {
            if (!tree_.node(id).leaf()) continue;
            power += (channel_sum(B_[id].v[0]) + channel_sum(B_[id].v[1])) * tree_.node(id).area;
        }
        const int max_sweeps = in_.settings.max_iterations > 0 ? in_.settings.max_iterations : 1000;
        int refinements = 0;
        while (power > 0.0 && sol.iterations < max_sweeps) {
            double change = sweep();
            ++sol.iterations;
            sol.residual = change / power;
            if (in_.progress) {
                char status[112];
                std::snprintf(status, sizeof status,
                              "sweep %d, change %.3g%%, %zu links, %zu nodes", sol.iterations,
                              100.0 * sol.residual, links_.size(), tree_.nodes().size());
                in_.progress->set_status(status);
                in_.progress->advance(0);
            }
            if (sol.residual >= in_.settings.tolerance) continue;
            // 3. Converged on these links: refine them by the new radiosities.
            if (refinements >= 8 || !refine_links()) break;
            ++refinements;
        }

        // The irradiance per leaf, and its direct part: the emitters' light along the links.
        sol.E.assign(tree_.nodes().size(), Sides{});
        sol.direct.assign(tree_.nodes().size(), Sides{});
        std::vector<Sides> emitted_gather = gather([&](uint32_t id, int side) {
            return side == 0 ? tree_.node(id).emission : Color(0.0f);
        });
        std::vector<Sides> total_gather =
            gather([&](uint32_t id, int side) { return B_[id].v[side]; });
        for (uint32_t r = 0; r < roots; ++r)
            push(r, Sides{}, Sides{}, total_gather, emitted_gather, sol);
        sol.rays = rays_;
        sol.links = links_.size();
        return sol;
    }

private:
    /// Whether some part of s lies in front of r's plane on a side, and of r on s's.
    bool facing(uint32_t r, uint32_t s) const {
        const ElementNode& a = tree_.node(r);
        const ElementNode& b = tree_.node(s);
        if (!(a.area > 0.0f) || !(b.area > 0.0f)) return false;
        auto straddles_or_off = [&](const ElementNode& plane_of, vec3 n, const ElementNode& other) {
            float lo = kInfinity, hi = -kInfinity;
            for (vec3 p : other.p) {
                float d = glm::dot(n, p - plane_of.centroid);
                lo = std::min(lo, d);
                hi = std::max(hi, d);
            }
            float eps = 1e-6f * plane_of.longest_edge();
            return hi > eps || lo < -eps;  // not in the plane
        };
        return straddles_or_off(a, tree_.normal(r), b) && straddles_or_off(b, tree_.normal(s), a);
    }

    /// The oracle: the light the link r <- s would carry, by a disc estimate of F from the
    /// centroids, F ~ A_s cos_r cos_s / (pi d^2 + A_s), an upper-bound-like estimate.
    float oracle(uint32_t r, uint32_t s) const {
        const ElementNode& a = tree_.node(r);
        const ElementNode& b = tree_.node(s);
        vec3 d = b.centroid - a.centroid;
        float d2 = glm::dot(d, d);
        vec3 w = d / std::sqrt(std::max(d2, 1e-30f));
        float cr = std::abs(glm::dot(tree_.normal(r), w));
        float cs = std::abs(glm::dot(tree_.normal(s), w));
        // Near nodes (d below their size) get cosines of 1: the centroids' cosines may vanish
        // where the nodes touch at an edge.
        float size = std::max(a.longest_edge(), b.longest_edge());
        if (d2 < size * size) cr = cs = 1.0f;
        float F = b.area * cr * cs / (kPi * d2 + b.area);
        int side = tree_.side_facing(s, a.centroid);
        return channel_sum(a.reflectance) / 3.0f * F * channel_sum(B_[s].v[side]);
    }

    bool can_split(uint32_t id) const {
        const ElementNode& n = tree_.node(id);
        return n.area > 0.0f && n.longest_edge() > min_edge_ &&
               (!n.leaf() || tree_.nodes().size() + 4 <= max_nodes_);
    }

    /// Refuses (an Error naming link_epsilon) a split past settings.max_links, counting the
    /// links still to come from the pairs not yet refined: a result that stopped refining
    /// where the links ran out would be wrong by tens of percent, and more links than the
    /// limit would take more memory than it allows (16 bytes each, twice while refine_links
    /// rebuilds them).
    void check_room_to_split() const {
        if (links_.size() + pending_ + 4 <= max_links_) return;
        throw Error(in_.file, "render.radiosity.link_epsilon",
                    "hierarchical radiosity would make more than " + std::to_string(max_links_) +
                        " links (render.radiosity.max_links); raise link_epsilon or max_links");
    }

    void refine(uint32_t r, uint32_t s) {
        if (oracle(r, s) > threshold_) {
            bool split_r = tree_.node(r).area >= tree_.node(s).area;
            uint32_t node = split_r ? r : s;
            if (!can_split(node)) {
                node = split_r ? s : r;
                split_r = !split_r;
            }
            if (can_split(node)) {
                check_room_to_split();
                uint32_t first = tree_.node(node).leaf() ? split(node) : tree_.node(node).child;
                for (uint32_t c = first; c < first + 4; ++c) {
                    if (split_r) {
                        refine(c, s);
                    } else {
                        refine(r, c);
                    }
                }
                return;
            }
        }
        links_.push_back(Link{r, s});  // its F is computed in finish_new_links()
    }

    uint32_t split(uint32_t id) {
        uint32_t first = tree_.split(id);
        grow_arrays();
        for (uint32_t c = first; c < first + 4; ++c) B_[c] = B_[id];
        return first;
    }

    void grow_arrays() {
        const size_t n = tree_.nodes().size();
        B_.resize(n);
        gathered_.resize(n);
        light_.resize(n);
        has_light_.resize(n, 0);
    }

    /// The lights' direct irradiance of every leaf that lacks it (in parallel).
    void light_for_new_leaves() {
        std::vector<uint32_t> todo;
        for (uint32_t id = 0; id < tree_.nodes().size(); ++id)
            if (tree_.node(id).leaf() && !has_light_[id]) todo.push_back(id);
        parallel_ranges(
            todo.size(), in_.threads,
            [&](size_t begin, size_t end) {
                for (size_t k = begin; k < end; ++k) light_[todo[k]] = in_.light_at(todo[k]);
            },
            64);
        for (uint32_t id : todo) has_light_[id] = 1;
    }

    /// B = E^e + rho L at the leaves, pulled up as area means.
    void initial_radiosity() {
        for (uint32_t r = 0; r < tree_.root_count(); ++r) pull_initial(r);
    }
    Sides pull_initial(uint32_t id) {
        const ElementNode& n = tree_.node(id);
        Sides b;
        if (n.leaf()) {
            b.v[0] = n.emission + n.reflectance * light_[id].v[0];
            b.v[1] = n.reflectance * light_[id].v[1];
        } else {
            uint32_t first = n.child;
            for (uint32_t c = first; c < first + 4; ++c) {
                Sides cb = pull_initial(c);
                for (int s = 0; s < 2; ++s) b.v[s] += 0.25f * cb.v[s];
            }
        }
        B_[id] = b;
        return b;
    }

    /// The form factors of the links made since the last call, in parallel; links that carry
    /// nothing are dropped.
    void finish_new_links() {
        std::vector<size_t> todo;
        for (size_t k = 0; k < links_.size(); ++k)
            if (links_[k].F[0] < 0.0f) todo.push_back(k);
        std::vector<uint64_t> rays(todo.size(), 0);
        parallel_ranges(
            todo.size(), in_.threads,
            [&](size_t begin, size_t end) {
                for (size_t k = begin; k < end; ++k) {
                    Link& l = links_[todo[k]];
                    FormFactor f = form_factor(in_.ff, l.receiver, l.source, in_.seed, rays[k]);
                    l.F[0] = f.F[0];
                    l.F[1] = f.F[1];
                }
            },
            64);
        for (uint64_t r : rays) rays_ += r;
        // A link that carries nothing goes, unless it may be refined later: its few rays
        // may all have been blocked where most of the nodes see each other.
        links_.erase(std::remove_if(links_.begin(), links_.end(),
                                    [&](const Link& l) {
                                        return !(l.F[0] + l.F[1] > 0.0f) &&
                                               !can_split(l.receiver) && !can_split(l.source);
                                    }),
                     links_.end());
        light_for_new_leaves();
    }

    /// Refines every link whose oracle now asks for it; true when any did.
    bool refine_links() {
        std::vector<Link> old;
        old.swap(links_);
        bool any = false;
        for (size_t k = 0; k < old.size(); ++k) {
            const Link& l = old[k];
            pending_ = old.size() - k - 1;
            bool splittable = can_split(l.receiver) || can_split(l.source);
            if (splittable && oracle(l.receiver, l.source) > threshold_) {  // BF refinement
                any = true;
                refine(l.receiver, l.source);
            } else {
                links_.push_back(l);
            }
        }
        pending_ = 0;
        if (any) {
            finish_new_links();
            // New leaves start from their parents' B; lights reach them through light_.
        }
        return any;
    }

    /// The irradiance every node gathers along its links from value(source, side).
    template <class Value>
    std::vector<Sides> gather(Value&& value) const {
        std::vector<Sides> g(tree_.nodes().size());
        for (const Link& l : links_) {
            // The source's side that faces the receiver's centroid, where F was estimated.
            Color b = value(l.source, tree_.side_facing(l.source, tree_.node(l.receiver).centroid));
            for (int side = 0; side < 2; ++side) g[l.receiver].v[side] += l.F[side] * b;
        }
        return g;
    }

    /// One sweep: gather, push down, pull up; returns the change of the leaves' power.
    double sweep() {
        gathered_ = gather([&](uint32_t id, int side) { return B_[id].v[side]; });
        std::vector<double> change(tree_.root_count(), 0.0);
        parallel_indices(tree_.root_count(), in_.threads, [&](size_t r) {
            change[r] = push_pull(static_cast<uint32_t>(r), Sides{});
        });
        double total = 0.0;
        for (double c : change) total += c;
        return total;
    }

    double push_pull(uint32_t id, Sides down) {
        const ElementNode& n = tree_.node(id);
        for (int s = 0; s < 2; ++s) down.v[s] += gathered_[id].v[s];
        Sides b;
        double change = 0.0;
        if (n.leaf()) {
            for (int s = 0; s < 2; ++s) {
                b.v[s] = (s == 0 ? n.emission : Color(0.0f)) +
                         n.reflectance * (light_[id].v[s] + down.v[s]);
                change += channel_sum(glm::abs(b.v[s] - B_[id].v[s])) * n.area;
            }
        } else {
            for (uint32_t c = n.child; c < n.child + 4; ++c) {
                change += push_pull(c, down);
                for (int s = 0; s < 2; ++s) b.v[s] += 0.25f * B_[c].v[s];
            }
        }
        B_[id] = b;
        return change;
    }

    /// The final irradiance of the leaves: what was gathered on the way down, plus L.
    void push(uint32_t id, Sides down, Sides down_direct, const std::vector<Sides>& total,
              const std::vector<Sides>& emitted, Solution& sol) const {
        const ElementNode& n = tree_.node(id);
        for (int s = 0; s < 2; ++s) {
            down.v[s] += total[id].v[s];
            down_direct.v[s] += emitted[id].v[s];
        }
        if (n.leaf()) {
            for (int s = 0; s < 2; ++s) {
                sol.E[id].v[s] = down.v[s] + light_[id].v[s];
                sol.direct[id].v[s] = down_direct.v[s] + light_[id].v[s];
            }
            return;
        }
        for (uint32_t c = n.child; c < n.child + 4; ++c)
            push(c, down, down_direct, total, emitted, sol);
    }

    SolverInput& in_;
    ElementTree& tree_;
    std::vector<Link> links_;
    std::vector<Sides> B_, gathered_, light_;
    std::vector<uint8_t> has_light_;
    float threshold_ = 0.0f;
    // The smallest nodes: as fine as adaptive subdivision goes below the elements.
    const float min_edge_ = std::ldexp(in_.settings.element_size, -in_.settings.max_subdivision);
    uint64_t rays_ = 0;

    size_t pending_ = 0;  // links to come: root pairs not yet refined, old links not placed back
    const size_t max_links_ = static_cast<size_t>(in_.settings.max_links);

public:
    size_t max_nodes_ = 0;
};

}  // namespace

Solution solve_hierarchical(SolverInput& in, size_t max_nodes) {
    Hierarchy h(in);
    h.max_nodes_ = max_nodes;
    return h.solve();
}

}  // namespace svetlo
