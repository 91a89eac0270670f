// The progressive solve split among ranks, and its checkpoint (docs/distributed.md,
// "Radiosity on many ranks"). The ranks are threads of this process here, exchanging through
// a ProcessGroup made of a barrier: the same calls mpirun's ranks make through MPI.
#include <gtest/gtest.h>

#include <atomic>
#include <barrier>
#include <cstring>
#include <thread>

#include "svetlo/core/error.h"
#include "svetlo/core/process_group.h"
#include "svetlo/radiosity/radiosity_engine.h"
#include "svetlo/scene/scene_loader.h"

namespace svetlo {
namespace {

using json = nlohmann::json;

/// N ranks as N threads: each all_gather puts its part in its slot, waits for all, reads
/// everything, and waits again before a slot is written anew.
class ThreadRanks {
public:
    explicit ThreadRanks(int n) : barrier_(n), parts_(static_cast<size_t>(n)) {}

    class Rank final : public ProcessGroup {
    public:
        Rank(ThreadRanks& all, int rank) : all_(all), rank_(rank) {}
        int rank() const override { return rank_; }
        int size() const override { return static_cast<int>(all_.parts_.size()); }
        void all_gather(const std::vector<std::byte>& mine, const std::vector<size_t>& counts,
                        std::vector<std::byte>& out) override {
            EXPECT_EQ(mine.size(), counts[static_cast<size_t>(rank_)]);
            all_.parts_[static_cast<size_t>(rank_)] = mine;
            all_.barrier_.arrive_and_wait();
            out.clear();
            for (const std::vector<std::byte>& part : all_.parts_)
                out.insert(out.end(), part.begin(), part.end());
            all_.barrier_.arrive_and_wait();
        }
        uint64_t sum(uint64_t value) override {
            std::vector<std::byte> mine(sizeof value), out;
            std::memcpy(mine.data(), &value, sizeof value);
            all_gather(mine, std::vector<size_t>(all_.parts_.size(), sizeof value), out);
            uint64_t total = 0;
            for (size_t k = 0; k < out.size(); k += sizeof value) {
                uint64_t one = 0;
                std::memcpy(&one, out.data() + k, sizeof one);
                total += one;
            }
            return total;
        }

    private:
        ThreadRanks& all_;
        int rank_;
    };

private:
    std::barrier<> barrier_;
    std::vector<std::vector<std::byte>> parts_;
};

/// The Cornell box of tests/data, small, by the progressive solver on uniform elements.
Scene cornell() {
    json j = {{"camera",
               {{"position", {0, 1, 3.9}}, {"look_at", {0, 1, 0}}, {"up", {0, 1, 0}}, {"fov", 38}}},
              {"film", {{"width", 32}, {"height", 32}}},
              {"render",
               {{"engine", "radiosity"},
                {"spp", 1},
                {"radiosity",
                 {{"element_size", 0.3},
                  {"patch_size", 3.0},  // 36 patches, 137 shots: few exchanges, a quick test
                  {"adaptive", 0},
                  {"solver", "progressive"},
                  {"tolerance", 1e-2}}}}}};
    j["objects"] = {{{"type", "mesh"},
                     {"file", std::string(SVETLO_SCENE_MODELS) + "/CornellBox-Original.obj"}}};
    return scene_from_json(j, "cornell.json");
}

/// Renders `scene` on `n` ranks (threads of one thread each), each with `options` and its
/// rank; returns every rank's result.
std::vector<RenderResult> render_on(int n, const Scene& scene,
                                    const std::vector<RenderOptions>& options) {
    ThreadRanks ranks(n);
    std::vector<RenderResult> results(static_cast<size_t>(n));
    std::vector<std::thread> threads;
    for (int r = 0; r < n; ++r) {
        threads.emplace_back([&, r] {
            ThreadRanks::Rank group(ranks, r);
            RenderOptions o = options[static_cast<size_t>(r)];
            o.threads = 1;
            o.group = &group;
            results[static_cast<size_t>(r)] = RadiosityRenderer().render(scene, o);
        });
    }
    for (std::thread& t : threads) t.join();
    return results;
}

std::vector<RenderOptions> same_options(int n, const RenderOptions& o = {}) {
    return std::vector<RenderOptions>(static_cast<size_t>(n), o);
}

/// The number after `what` in a summary detail ("1234 shots").
long number_before(const std::string& detail, const std::string& what) {
    const size_t at = detail.find(" " + what);
    if (at == std::string::npos) return -1;
    const size_t from = detail.rfind(' ', at - 1);
    return std::stol(detail.substr(from + 1, at - from - 1));
}

TEST(DistributedSolve, AnyNumberOfRanksMakesTheImageOfOne) {
    // Each rank makes its patches' part of every row and the ranks exchange the unshot light:
    // every rank's image is the one process's, bit for bit, and the rays are split among the
    // ranks, not repeated.
    const Scene scene = cornell();
    RenderOptions alone;
    alone.threads = 1;
    const RenderResult one = RadiosityRenderer().render(scene, alone);
    const long shots = number_before(one.stats.detail, "shots");
    ASSERT_GT(shots, 20) << one.stats.detail;
    for (int n : {1, 2, 3}) {
        const std::vector<RenderResult> many = render_on(n, scene, same_options(n));
        for (int r = 0; r < n; ++r) {
            const RenderResult& mine = many[static_cast<size_t>(r)];
            EXPECT_EQ(mine.color.pixels, one.color.pixels) << n << " ranks, rank " << r;
            EXPECT_EQ(number_before(mine.stats.detail, "shots"), shots) << mine.stats.detail;
            EXPECT_EQ(mine.stats.rays, one.stats.rays) << n << " ranks: the rays, summed";
        }
    }
}

/// A --checkpoint in memory: what was saved last, and how often.
struct MemoryCheckpoint {
    int passes = 0, saves = 0;
    std::vector<double> state;
    Checkpoint callbacks() {
        Checkpoint c;
        c.restore = [this](std::vector<double>& into) {
            if (passes == 0) return 0;
            EXPECT_TRUE(into.empty()) << "the solve takes the state whatever its size";
            into = state;
            return passes;
        };
        c.save = [this](int p, const std::vector<double>& s) {
            passes = p;
            state = s;
            ++saves;
        };
        return c;
    }
};

TEST(DistributedSolve, AnInterruptedSolveResumesBitForBit) {
    // Stopped (as by SIGINT) after a few shots, the solve saves them and shows the solution as
    // it stands; resumed from the save, on any number of ranks, it ends in the uninterrupted
    // image, and a finished save gives that image again without making its rows again.
    const Scene scene = cornell();
    RenderOptions plain;
    plain.threads = 1;
    const RenderResult whole = RadiosityRenderer().render(scene, plain);
    for (int stop_on : {1, 2}) {
        for (int resume_on : {1, 3}) {
            MemoryCheckpoint saved;
            const Checkpoint callbacks = saved.callbacks();
            std::atomic<bool> cancel{false};
            std::vector<RenderOptions> first = same_options(stop_on);
            for (RenderOptions& o : first) {
                o.checkpoint = &callbacks;
                o.cancel = &cancel;
            }
            // The snapshots (after 0, 1, 2, 4 ... shots) stop it after the fourth shot.
            int snapshots = 0;
            first[0].on_pass = [&](int, double, const Image&) {
                if (++snapshots == 4) cancel = true;
            };
            const RenderResult stopped = render_on(stop_on, scene, first)[0];
            EXPECT_EQ(saved.passes, 5) << "saved after the shot in progress";
            EXPECT_EQ(saved.saves, 1) << "only rank 0 saves, once at the end here";
            EXPECT_NE(stopped.color.pixels, whole.color.pixels);

            std::vector<RenderOptions> second = same_options(resume_on);
            for (RenderOptions& o : second) o.checkpoint = &callbacks;
            const RenderResult resumed = render_on(resume_on, scene, second)[0];
            EXPECT_EQ(resumed.color.pixels, whole.color.pixels)
                << "stopped on " << stop_on << ", resumed on " << resume_on;
            EXPECT_GT(saved.passes, 5);
            const RenderResult again = render_on(1, scene, same_options(1, second[0]))[0];
            EXPECT_EQ(again.color.pixels, whole.color.pixels);
            // The rows came with the save: only the emitter's (shot before the state is
            // restored: one row of the 36 patches') was made again.
            EXPECT_LT(again.stats.rays * 10, whole.stats.rays);
        }
    }
}

TEST(DistributedSolve, OtherSolversRefuseACheckpoint) {
    Scene scene = cornell();
    scene.render.radiosity.solver = RadiositySolver::Hierarchical;
    MemoryCheckpoint saved;
    const Checkpoint callbacks = saved.callbacks();
    RenderOptions options;
    options.checkpoint = &callbacks;
    try {
        RadiosityRenderer().render(scene, options);
        FAIL() << "a hierarchical solve with a checkpoint was not refused";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("--checkpoint"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("hierarchical"), std::string::npos) << e.what();
    }
    EXPECT_EQ(saved.saves, 0);
}

TEST(DistributedSolve, DealByWeightGivesEachRankItsShare) {
    // Each item to the least loaded rank so far: about equal weights, neighbours apart.
    EXPECT_EQ(deal_by_weight({1, 1, 1, 1}, 2), (std::vector<int>{0, 1, 0, 1}));
    EXPECT_EQ(deal_by_weight({4, 1, 1, 1, 1}, 2), (std::vector<int>{0, 1, 1, 1, 1}));
    EXPECT_EQ(deal_by_weight({1, 1}, 3), (std::vector<int>{0, 1}));
    EXPECT_EQ(deal_by_weight({}, 2), (std::vector<int>{}));
    EXPECT_EQ(deal_by_weight({5, 2}, 1), (std::vector<int>{0, 0}));
}

}  // namespace
}  // namespace svetlo
