#include "distributed.h"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <functional>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "svetlo/core/error.h"
#include "svetlo/core/process_group.h"
#include "svetlo/job/engines.h"

#ifdef SVETLO_MPI
#include <mpi.h>
#endif

namespace svetlo {

#ifdef SVETLO_MPI

namespace {

/// The tiles of `window`, in a fixed order: 32 x 32 pixels for the ray tracers, whose cost
/// is per pixel; for the engines that draw the whole frame at once (raster, radiosity), whose
/// windows redraw the frame or its item buffers, 4 bands per rank, full width.
std::vector<Crop> make_tiles(const Crop& window, const std::string& engine, int ranks) {
    std::vector<Crop> tiles;
    const bool bands = capabilities_of(engine, "").whole_frame;
    const int th = bands ? std::max(1, (window.height() + 4 * ranks - 1) / (4 * ranks)) : 32;
    const int tw = bands ? window.width() : 32;
    for (int y = window.y0; y < window.y1; y += th)
        for (int x = window.x0; x < window.x1; x += tw)
            tiles.push_back({x, std::min(x + tw, window.x1), y, std::min(y + th, window.y1)});
    return tiles;
}

/// Where `part` (the result of tile `tile`) goes in `full` (the window's images): images of
/// the tile's size are pasted at its place; others (a shadow map) are the frame's, kept once.
void paste(RenderResult& full, const Crop& window, const Crop& tile, RenderResult&& part) {
    auto put = [&](Image& into, Image&& from) {
        if (from.width != tile.width() || from.height != tile.height()) {
            if (into.width == 0) into = std::move(from);
            return;
        }
        for (int j = 0; j < from.height; ++j)
            for (int i = 0; i < from.width; ++i)
                into.at(tile.x0 - window.x0 + i, tile.y0 - window.y0 + j) = from.at(i, j);
    };
    put(full.color, std::move(part.color));
    for (auto& [name, image] : part.aovs) {
        Image& into = full.aovs[name];
        if (into.width == 0 && image.width == tile.width() && image.height == tile.height())
            into = Image(window.width(), window.height());
        put(into, std::move(image));
    }
}

/// SVETLO_TEST_SLOW_RANK=R:F (tests and docs/distributed.md only): rank R takes F times as
/// long over each tile, as a slower machine would.
double slowdown(int rank) {
    const char* spec = std::getenv("SVETLO_TEST_SLOW_RANK");
    if (!spec) return 1.0;
    const std::string s(spec);
    const size_t colon = s.find(':');
    if (colon == std::string::npos || std::atoi(s.substr(0, colon).c_str()) != rank) return 1.0;
    return std::max(1.0, std::atof(s.substr(colon + 1).c_str()));
}

}  // namespace

namespace {

enum Tag { kRequest = 1, kAssign = 2, kResult = 3, kDone = 4 };

/// The job's ranks as the library's ProcessGroup: the radiosity solve splits over them.
/// (MPI_THREAD_FUNNELED: the engines call it from the thread that runs them.)
class MpiGroup final : public ProcessGroup {
public:
    MpiGroup(int rank, int size) : rank_(rank), size_(size) {}
    int rank() const override { return rank_; }
    int size() const override { return size_; }
    void all_gather(const std::vector<std::byte>& mine, const std::vector<size_t>& counts,
                    std::vector<std::byte>& all) override {
        std::vector<int> sizes(counts.size()), displs(counts.size(), 0);
        for (size_t r = 0; r < counts.size(); ++r) {
            sizes[r] = static_cast<int>(counts[r]);
            if (r > 0) displs[r] = displs[r - 1] + sizes[r - 1];
        }
        all.resize(static_cast<size_t>(displs.back() + sizes.back()));
        MPI_Allgatherv(mine.data(), static_cast<int>(mine.size()), MPI_BYTE, all.data(),
                       sizes.data(), displs.data(), MPI_BYTE, MPI_COMM_WORLD);
        received_ += all.size() - mine.size();
    }
    /// Bytes this rank received from the others.
    uint64_t received() const { return received_; }
    uint64_t sum(uint64_t value) override {
        uint64_t out = 0;
        MPI_Allreduce(&value, &out, 1, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
        return out;
    }

private:
    int rank_, size_;
    uint64_t received_ = 0;
};

/// --checkpoint under mpirun for the ray tracers (Layout::Tiles): the tiles done, each as its
/// index, its message's length and its message (pack), as doubles. Every rank reads them, so
/// that a file that does not fit this render stops them all alike.
std::map<int, std::vector<float>> saved_tiles(const CheckpointFile* checkpoint, size_t tiles,
                                              const std::string& file) {
    std::map<int, std::vector<float>> out;
    if (!checkpoint || checkpoint->resumed_passes() == 0) return out;
    const std::vector<double>& state = checkpoint->saved();
    for (size_t pos = 0; pos < state.size();) {
        const double index = state[pos], length = pos + 1 < state.size() ? state[pos + 1] : -1.0;
        if (!(index >= 0.0 && index < static_cast<double>(tiles)) || !(length >= 0.0) ||
            length > static_cast<double>(state.size() - pos - 2)) {
            throw Error(file, "--checkpoint", "holds tiles that do not fit this render");
        }
        pos += 2;
        std::vector<float>& data = out[static_cast<int>(index)];
        data.assign(state.begin() + static_cast<std::ptrdiff_t>(pos),
                    state.begin() + static_cast<std::ptrdiff_t>(pos + static_cast<size_t>(length)));
        pos += static_cast<size_t>(length);
    }
    return out;
}

/// How often rank 0 saves the tiles done, seconds (and once at the end).
constexpr double kSaveSeconds = 1.0;

/// Tiles a worker asks for ahead: it renders one while the answer for the next comes, so it
/// never waits for rank 0 to finish a tile of its own.
constexpr int kAhead = 4;

/// A tile's images in one message: for each image, in name order (the colour first), its
/// width and height as two floats, then its pixels.
std::vector<float> pack(const RenderResult& r) {
    std::vector<float> out;
    auto add = [&](const Image& image) {
        out.push_back(static_cast<float>(image.width));
        out.push_back(static_cast<float>(image.height));
        for (const Color& c : image.pixels) out.insert(out.end(), {c.r, c.g, c.b});
    };
    add(r.color);
    for (const auto& [name, image] : r.aovs) add(image);  // std::map: name order
    return out;
}

RenderResult unpack(const std::vector<float>& data, const std::vector<std::string>& names) {
    RenderResult r;
    size_t pos = 0;
    auto take = [&](Image& image) {
        const int w = static_cast<int>(data[pos]), h = static_cast<int>(data[pos + 1]);
        pos += 2;
        image = Image(w, h);
        for (Color& c : image.pixels) {
            c = Color(data[pos], data[pos + 1], data[pos + 2]);
            pos += 3;
        }
    };
    take(r.color);
    for (const std::string& name : names) take(r.aovs[name]);
    return r;
}

}  // namespace

MpiSession::MpiSession(int& argc, char**& argv) {
    // Started only under a launcher: a plain run stays a plain program.
    if (!std::getenv("OMPI_COMM_WORLD_SIZE") && !std::getenv("PMI_SIZE")) return;
    int provided = 0;
    MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
    started_ = true;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

MpiSession::~MpiSession() {
    if (started_) MPI_Finalize();
}

void MpiSession::abort(int status) const {
    if (started_ && size_ > 1) MPI_Abort(MPI_COMM_WORLD, status);
    std::exit(status);
}

RenderResult run_job_distributed(const RenderJob& job, const MpiSession& mpi,
                                 DistributedStats& stats, const CheckpointFile* checkpoint) {
    if (mpi.size() == 1) return run_job(job);
    const int ranks = mpi.size();
    const Crop window = film_window(job.scene, job.options);
    const std::vector<Crop> tiles = make_tiles(window, job.scene.render.engine, ranks);
    const bool bands = capabilities_of(job.scene.render.engine, "").whole_frame;
    const double slow = slowdown(mpi.rank());
    RenderJob local = job;
    local.options.progress = false;
    local.options.crop.reset();
    MpiGroup group(mpi.rank(), ranks);
    local.options.group = &group;
    // The tiles a checkpoint holds (Layout::Tiles; rank 0 pastes them and hands out the rest).
    std::map<int, std::vector<float>> kept =
        saved_tiles(checkpoint, tiles.size(), job.scene.path.string());
    stats.resumed_tiles = static_cast<int>(kept.size());
    if (mpi.rank() != 0) kept.clear();
    RenderResult full;  // rank 0: the window's images
    // The images a tile carries besides the colour: the AOVs the job asks for (the engines
    // name them so), in name order on every rank, as pack sends a result's std::map.
    std::vector<std::string> names = job.options.aovs;
    names.insert(names.end(), job.options.debug_aovs.begin(), job.options.debug_aovs.end());
    std::sort(names.begin(), names.end());
    names.erase(std::unique(names.begin(), names.end()), names.end());  // one AOV, two files
    uint64_t bytes = 0;
    auto clock = std::chrono::steady_clock::now();
    auto pace = [&]() {  // the test's slow rank: wait (F - 1) times the tile's time
        if (slow <= 1.0) return;
        const auto took = std::chrono::steady_clock::now() - clock;
        std::this_thread::sleep_for(
            std::chrono::duration_cast<std::chrono::nanoseconds>(took * (slow - 1.0)));
    };

    // The state the window source's callbacks keep, alive as long as the render.
    // Rank 0:
    size_t next = 0;                                   // the next tile to hand out
    int own = -1;                                      // the tile it renders itself
    auto saved_at = std::chrono::steady_clock::now();  // the checkpoint's last save
    std::function<void()> finish;  // after the last tile: the checkpoint's last save
    int finished = 0;              // workers that said they are done (after their last result)
    // A worker:
    std::vector<int> queue;  // tiles assigned and not yet begun, in order
    int asked = 0;           // requests not yet answered
    bool exhausted = false;  // rank 0 answered -1: no tile left
    int index = -1;          // the tile being rendered
    // Results in flight: sent without waiting (a tile is larger than the eager limit, and rank
    // 0 receives only between tiles of its own), kept until their sends complete.
    std::vector<std::vector<float>> sending;
    std::vector<MPI_Request> requests;

    // SIGINT or SIGTERM: the ray tracers' tiles stop; the whole-frame engines' few bands are
    // drawn (the radiosity solve stops itself, and its image is displayed).
    auto interrupted = [&] { return !bands && job.options.cancel && job.options.cancel->load(); };
    WindowSource source;
    if (mpi.rank() == 0) {
        full.color = Image(window.width(), window.height());
        // The tiles done, kept as sent and saved (checkpoint, Layout::Tiles).
        auto save = [&, checkpoint](bool now) {
            if (!checkpoint || kept.empty()) return;
            const auto at = std::chrono::steady_clock::now();
            if (!now && std::chrono::duration<double>(at - saved_at).count() < kSaveSeconds) return;
            std::vector<double> state;
            for (const auto& [tile, data] : kept) {
                state.push_back(tile);
                state.push_back(static_cast<double>(data.size()));
                state.insert(state.end(), data.begin(), data.end());
            }
            checkpoint->save(static_cast<int>(kept.size()), state);
            saved_at = at;
        };
        auto keep = [&, checkpoint, save](int t, const Crop& tile, std::vector<float>&& data) {
            RenderResult part = unpack(data, names);
            if (checkpoint) kept[t] = std::move(data);
            paste(full, window, tile, std::move(part));
            save(false);
        };
        for (const auto& [t, data] : kept)
            paste(full, window, tiles[static_cast<size_t>(t)], unpack(data, names));
        auto take = [&] {  // the next tile not done, or tiles.size()
            while (next < tiles.size() && kept.count(static_cast<int>(next))) ++next;
            return next < tiles.size() ? next++ : tiles.size();
        };
        auto handle = [&, keep, take](const MPI_Status& status) {
            if (status.MPI_TAG == kRequest || status.MPI_TAG == kDone) {
                MPI_Recv(nullptr, 0, MPI_INT, status.MPI_SOURCE, status.MPI_TAG, MPI_COMM_WORLD,
                         MPI_STATUS_IGNORE);
                if (status.MPI_TAG == kDone) {
                    ++finished;
                    return;
                }
                const size_t t = take();
                int given = t < tiles.size() ? static_cast<int>(t) : -1;
                MPI_Send(&given, 1, MPI_INT, status.MPI_SOURCE, kAssign, MPI_COMM_WORLD);
                return;
            }
            int count = 0;
            MPI_Get_count(&status, MPI_FLOAT, &count);
            std::vector<float> data(static_cast<size_t>(count));
            MPI_Recv(data.data(), count, MPI_FLOAT, status.MPI_SOURCE, kResult, MPI_COMM_WORLD,
                     MPI_STATUS_IGNORE);
            const auto tile = static_cast<int>(data.back());
            data.pop_back();
            keep(tile, tiles[static_cast<size_t>(tile)], std::move(data));
            bytes += static_cast<uint64_t>(count) * sizeof(float);
        };
        // (The helpers are copied in: they end with this block; what they use does not.)
        source.next = [&, handle, interrupted, take](Crop& w) {
            // SIGINT or SIGTERM (every rank gets it from mpirun): no tile is begun after it;
            // the tiles in progress end their pass and come in, the others stay black.
            if (interrupted()) next = tiles.size();
            for (int flag = 1; flag;) {  // answer every rank that asked meanwhile
                MPI_Status status;
                MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status);
                if (flag) handle(status);
            }
            if (const size_t t = take(); t < tiles.size()) {
                own = static_cast<int>(t);
                w = tiles[t];
                clock = std::chrono::steady_clock::now();
                return true;
            }
            // A worker's results come before its kDone (messages between two ranks keep
            // their order), so every tile is in once all are done.
            while (finished < ranks - 1) {
                MPI_Status status;
                MPI_Probe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &status);
                handle(status);
            }
            return false;
        };
        source.done = [&, keep](const Crop& w, RenderResult&& r) {
            pace();
            ++stats.rank0_tiles;
            if (checkpoint)
                keep(own, w, pack(r));
            else
                paste(full, window, w, std::move(r));
        };
        finish = [save] { save(true); };
    } else {
        auto reap = [&](bool all) {
            for (size_t k = 0; k < requests.size();) {
                int complete = 0;
                if (all) {
                    MPI_Wait(&requests[k], MPI_STATUS_IGNORE);
                    complete = 1;
                } else {
                    MPI_Test(&requests[k], &complete, MPI_STATUS_IGNORE);
                }
                if (!complete) {
                    ++k;
                    continue;
                }
                requests.erase(requests.begin() + static_cast<std::ptrdiff_t>(k));
                sending.erase(sending.begin() + static_cast<std::ptrdiff_t>(k));
            }
        };
        source.next = [&, reap, interrupted](Crop& w) {
            reap(false);
            if (interrupted()) {  // begin nothing more; collect the answers still due
                exhausted = true;
                queue.clear();
            }
            while (!exhausted && static_cast<int>(queue.size()) + asked < kAhead) {
                MPI_Send(nullptr, 0, MPI_INT, 0, kRequest, MPI_COMM_WORLD);
                ++asked;
            }
            while (queue.empty() && asked > 0) {
                int answer = -1;
                MPI_Recv(&answer, 1, MPI_INT, 0, kAssign, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
                --asked;
                if (answer < 0)
                    exhausted = true;
                else if (!interrupted())
                    queue.push_back(answer);
            }
            if (queue.empty()) {  // every request answered, the last with -1
                reap(true);
                MPI_Send(nullptr, 0, MPI_INT, 0, kDone, MPI_COMM_WORLD);
                return false;
            }
            index = queue.front();
            queue.erase(queue.begin());
            w = tiles[static_cast<size_t>(index)];
            clock = std::chrono::steady_clock::now();
            return true;
        };
        source.done = [&](const Crop&, RenderResult&& r) {
            pace();
            sending.push_back(pack(r));
            sending.back().push_back(static_cast<float>(index));
            requests.emplace_back();
            MPI_Isend(sending.back().data(), static_cast<int>(sending.back().size()), MPI_FLOAT, 0,
                      kResult, MPI_COMM_WORLD, &requests.back());
        };
    }
    local.options.windows = &source;
    RenderResult result = run_job(local);
    if (finish) finish();
    const uint64_t exchanged = group.received();
    MPI_Reduce(&exchanged, &stats.exchanged, 1, MPI_UINT64_T, MPI_SUM, 0, MPI_COMM_WORLD);
    uint64_t total_rays = 0, total_nonfinite = 0;
    MPI_Reduce(&result.stats.rays, &total_rays, 1, MPI_UINT64_T, MPI_SUM, 0, MPI_COMM_WORLD);
    MPI_Reduce(&result.stats.nonfinite, &total_nonfinite, 1, MPI_UINT64_T, MPI_SUM, 0,
               MPI_COMM_WORLD);
    if (mpi.rank() != 0) return {};
    full.stats = result.stats;
    full.stats.rays = total_rays;
    full.stats.nonfinite = total_nonfinite;
    stats.tiles = static_cast<int>(tiles.size());
    stats.bytes = bytes;
    return full;
}

#else  // one process

MpiSession::MpiSession(int&, char**&) {}
MpiSession::~MpiSession() = default;
void MpiSession::abort(int status) const { std::exit(status); }

RenderResult run_job_distributed(const RenderJob& job, const MpiSession&, DistributedStats&,
                                 const CheckpointFile*) {
    return run_job(job);
}

#endif

}  // namespace svetlo
