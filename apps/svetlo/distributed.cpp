#include "distributed.h"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <functional>
#include <map>
#include <optional>
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

namespace {

using Clock = std::chrono::steady_clock;

/// The test's slow rank (slowdown): after each tile it waits (F - 1) times the tile's time.
class Pacer {
public:
    explicit Pacer(double slow) : slow_(slow) {}
    void start() { clock_ = Clock::now(); }
    void pace() const {
        if (slow_ <= 1.0) return;
        const auto took = Clock::now() - clock_;
        std::this_thread::sleep_for(
            std::chrono::duration_cast<std::chrono::nanoseconds>(took * (slow_ - 1.0)));
    }

private:
    double slow_;
    Clock::time_point clock_ = Clock::now();
};

/// Rank 0's side of the tiles: it hands them out, to itself and to every worker that asks,
/// pastes what comes back into the window's images, and keeps and saves them for
/// --checkpoint (Layout::Tiles).
class TileMaster {
public:
    TileMaster(const std::vector<Crop>& tiles, const Crop& window,
               const std::vector<std::string>& names, const CheckpointFile* checkpoint,
               std::map<int, std::vector<float>> kept, int ranks, Pacer& pacer,
               DistributedStats& stats)
        : tiles_(tiles),
          window_(window),
          names_(names),
          checkpoint_(checkpoint),
          kept_(std::move(kept)),
          ranks_(ranks),
          pacer_(pacer),
          stats_(stats) {
        full_.color = Image(window.width(), window.height());
        for (const auto& [t, data] : kept_)
            paste(full_, window_, tiles_[static_cast<size_t>(t)], unpack(data, names_));
    }

    /// The next tile rank 0 renders itself, after answering every rank that asked
    /// meanwhile; false when none is left and every worker's results are in.
    bool next(Crop& w, bool interrupted) {
        // SIGINT or SIGTERM (every rank gets it from mpirun): no tile is begun after it; the
        // tiles in progress end their pass and come in, the others stay black.
        if (interrupted) next_ = tiles_.size();
        for (int flag = 1; flag;) {
            MPI_Status status;
            MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status);
            if (flag) handle(status);
        }
        if (const size_t t = take(); t < tiles_.size()) {
            own_ = static_cast<int>(t);
            w = tiles_[t];
            pacer_.start();
            return true;
        }
        // A worker's results come before its kDone (messages between two ranks keep their
        // order), so every tile is in once all are done.
        while (finished_ < ranks_ - 1) {
            MPI_Status status;
            MPI_Probe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &status);
            handle(status);
        }
        return false;
    }

    /// Rank 0's own tile, rendered.
    void done(const Crop& w, RenderResult&& r) {
        pacer_.pace();
        ++stats_.rank0_tiles;
        if (checkpoint_)
            keep(own_, w, pack(r));
        else
            paste(full_, window_, w, std::move(r));
    }

    /// After the last tile: the checkpoint's last save; the window's images.
    RenderResult finish() {
        save(true);
        return std::move(full_);
    }

    uint64_t bytes() const { return bytes_; }

private:
    /// The next tile not done, or tiles.size().
    size_t take() {
        while (next_ < tiles_.size() && kept_.count(static_cast<int>(next_))) ++next_;
        return next_ < tiles_.size() ? next_++ : tiles_.size();
    }

    /// A worker's message: a request for a tile (answered with one, or -1), its last word
    /// (kDone), or a tile's result.
    void handle(const MPI_Status& status) {
        if (status.MPI_TAG == kRequest || status.MPI_TAG == kDone) {
            MPI_Recv(nullptr, 0, MPI_INT, status.MPI_SOURCE, status.MPI_TAG, MPI_COMM_WORLD,
                     MPI_STATUS_IGNORE);
            if (status.MPI_TAG == kDone) {
                ++finished_;
                return;
            }
            const size_t t = take();
            int given = t < tiles_.size() ? static_cast<int>(t) : -1;
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
        keep(tile, tiles_[static_cast<size_t>(tile)], std::move(data));
        bytes_ += static_cast<uint64_t>(count) * sizeof(float);
    }

    /// A tile done: pasted, and kept (and saved now and then) for the checkpoint.
    void keep(int t, const Crop& tile, std::vector<float>&& data) {
        RenderResult part = unpack(data, names_);
        if (checkpoint_) kept_[t] = std::move(data);
        paste(full_, window_, tile, std::move(part));
        save(false);
    }

    /// The tiles done, as sent, into the checkpoint: about every kSaveSeconds, or `now`.
    void save(bool now) {
        if (!checkpoint_ || kept_.empty()) return;
        const auto at = Clock::now();
        if (!now && std::chrono::duration<double>(at - saved_at_).count() < kSaveSeconds) return;
        std::vector<double> state;
        for (const auto& [tile, data] : kept_) {
            state.push_back(tile);
            state.push_back(static_cast<double>(data.size()));
            state.insert(state.end(), data.begin(), data.end());
        }
        checkpoint_->save(static_cast<int>(kept_.size()), state);
        saved_at_ = at;
    }

    const std::vector<Crop>& tiles_;
    Crop window_;
    const std::vector<std::string>& names_;
    const CheckpointFile* checkpoint_;
    std::map<int, std::vector<float>> kept_;  // the tiles done, as sent (with a checkpoint)
    int ranks_;
    Pacer& pacer_;
    DistributedStats& stats_;
    RenderResult full_;   // the window's images
    size_t next_ = 0;     // the next tile to hand out
    int own_ = -1;        // the tile rank 0 renders itself
    int finished_ = 0;    // workers that said they are done (after their last result)
    uint64_t bytes_ = 0;  // received
    Clock::time_point saved_at_ = Clock::now();  // the checkpoint's last save
};

/// A worker's side: it asks rank 0 for tiles ahead (kAhead), renders them in order and sends
/// each result without waiting, then says it is done.
class TileWorker {
public:
    TileWorker(const std::vector<Crop>& tiles, Pacer& pacer) : tiles_(tiles), pacer_(pacer) {}

    /// The next tile assigned; false (after its last results are sent and kDone) when rank 0
    /// has none left, or once `interrupted` says so.
    bool next(Crop& w, const std::function<bool()>& interrupted) {
        reap(false);
        if (interrupted()) {  // begin nothing more; collect the answers still due
            exhausted_ = true;
            queue_.clear();
        }
        while (!exhausted_ && static_cast<int>(queue_.size()) + asked_ < kAhead) {
            MPI_Send(nullptr, 0, MPI_INT, 0, kRequest, MPI_COMM_WORLD);
            ++asked_;
        }
        while (queue_.empty() && asked_ > 0) {
            int answer = -1;
            MPI_Recv(&answer, 1, MPI_INT, 0, kAssign, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            --asked_;
            if (answer < 0)
                exhausted_ = true;
            else if (!interrupted())
                queue_.push_back(answer);
        }
        if (queue_.empty()) {  // every request answered, the last with -1
            reap(true);
            MPI_Send(nullptr, 0, MPI_INT, 0, kDone, MPI_COMM_WORLD);
            return false;
        }
        index_ = queue_.front();
        queue_.erase(queue_.begin());
        w = tiles_[static_cast<size_t>(index_)];
        pacer_.start();
        return true;
    }

    /// The tile rendered: sent to rank 0 without waiting, its index last.
    void done(RenderResult&& r) {
        pacer_.pace();
        sending_.push_back(pack(r));
        sending_.back().push_back(static_cast<float>(index_));
        requests_.emplace_back();
        MPI_Isend(sending_.back().data(), static_cast<int>(sending_.back().size()), MPI_FLOAT, 0,
                  kResult, MPI_COMM_WORLD, &requests_.back());
    }

private:
    /// Frees the results whose sends are complete (with `all`, waits for every one).
    void reap(bool all) {
        for (size_t k = 0; k < requests_.size();) {
            int complete = 0;
            if (all) {
                MPI_Wait(&requests_[k], MPI_STATUS_IGNORE);
                complete = 1;
            } else {
                MPI_Test(&requests_[k], &complete, MPI_STATUS_IGNORE);
            }
            if (!complete) {
                ++k;
                continue;
            }
            requests_.erase(requests_.begin() + static_cast<std::ptrdiff_t>(k));
            sending_.erase(sending_.begin() + static_cast<std::ptrdiff_t>(k));
        }
    }

    const std::vector<Crop>& tiles_;
    Pacer& pacer_;
    std::vector<int> queue_;  // tiles assigned and not yet begun, in order
    int asked_ = 0;           // requests not yet answered
    bool exhausted_ = false;  // rank 0 answered -1: no tile left
    int index_ = -1;          // the tile being rendered
    // Results in flight: sent without waiting (a tile is larger than the eager limit, and rank
    // 0 receives only between tiles of its own), kept until their sends complete.
    std::vector<std::vector<float>> sending_;
    std::vector<MPI_Request> requests_;
};

}  // namespace

RenderResult run_job_distributed(const RenderJob& job, const MpiSession& mpi,
                                 DistributedStats& stats, const CheckpointFile* checkpoint) {
    if (mpi.size() == 1) return run_job(job);
    const int ranks = mpi.size();
    const Crop window = film_window(job.scene, job.options);
    const std::vector<Crop> tiles = make_tiles(window, job.scene.render.engine, ranks);
    const bool bands = capabilities_of(job.scene.render.engine, "").whole_frame;
    RenderJob local = job;
    local.options.progress = false;
    local.options.crop.reset();
    MpiGroup group(mpi.rank(), ranks);
    local.options.group = &group;
    // The tiles a checkpoint holds (Layout::Tiles; rank 0 pastes them and hands out the rest).
    std::map<int, std::vector<float>> kept =
        saved_tiles(checkpoint, tiles.size(), job.scene.path.string());
    stats.resumed_tiles = static_cast<int>(kept.size());
    // The images a tile carries besides the colour: the AOVs the job asks for (the engines
    // name them so), in name order on every rank, as pack sends a result's std::map.
    std::vector<std::string> names = job.options.aovs;
    names.insert(names.end(), job.options.debug_aovs.begin(), job.options.debug_aovs.end());
    std::sort(names.begin(), names.end());
    names.erase(std::unique(names.begin(), names.end()), names.end());  // one AOV, two files
    Pacer pacer(slowdown(mpi.rank()));
    // SIGINT or SIGTERM: the ray tracers' tiles stop; the whole-frame engines' few bands are
    // drawn (the radiosity solve stops itself, and its image is displayed).
    const std::function<bool()> interrupted = [&] {
        return !bands && job.options.cancel && job.options.cancel->load();
    };
    std::optional<TileMaster> master;
    std::optional<TileWorker> worker;
    WindowSource source;
    if (mpi.rank() == 0) {
        master.emplace(tiles, window, names, checkpoint, std::move(kept), ranks, pacer, stats);
        source.next = [&](Crop& w) { return master->next(w, interrupted()); };
        source.done = [&](const Crop& w, RenderResult&& r) { master->done(w, std::move(r)); };
    } else {
        worker.emplace(tiles, pacer);
        source.next = [&](Crop& w) { return worker->next(w, interrupted); };
        source.done = [&](const Crop&, RenderResult&& r) { worker->done(std::move(r)); };
    }
    local.options.windows = &source;
    RenderResult result = run_job(local);
    RenderResult full = master ? master->finish() : RenderResult{};
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
    stats.bytes = master->bytes();
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
