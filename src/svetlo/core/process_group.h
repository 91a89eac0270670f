// The processes that share one render's setup (docs/distributed.md): under mpirun, its ranks.
// An engine whose setup is worth splitting (the radiosity solve) gives each rank a part and
// exchanges the parts through this interface; the library knows nothing of MPI, which
// apps/svetlo/distributed.cpp implements it with. Every call is collective: every rank of
// the group makes it, in the same order.
#pragma once

#include <cstdint>
#include <vector>

namespace svetlo {

class ProcessGroup {
public:
    virtual ~ProcessGroup() = default;
    virtual int rank() const = 0;
    virtual int size() const = 0;
    /// Every rank gives its own bytes; each gets all of them, rank 0's first, then rank 1's...
    /// `counts[r]` is rank r's number of bytes, which every rank knows.
    virtual void all_gather(const std::vector<std::byte>& mine, const std::vector<size_t>& counts,
                            std::vector<std::byte>& all) = 0;
    /// The sum of `value` over the ranks, on every rank.
    virtual uint64_t sum(uint64_t value) = 0;
};

/// Deals `weights.size()` items out to `ranks` ranks, each item in turn to the rank with the
/// least weight so far (the lowest such rank): about the same weight each, and neighbouring
/// items to different ranks. Returns each item's rank.
inline std::vector<int> deal_by_weight(const std::vector<size_t>& weights, int ranks) {
    std::vector<size_t> load(static_cast<size_t>(ranks), 0);
    std::vector<int> owner(weights.size(), 0);
    for (size_t i = 0; i < weights.size(); ++i) {
        size_t least = 0;
        for (size_t r = 1; r < load.size(); ++r)
            if (load[r] < load[least]) least = r;
        owner[i] = static_cast<int>(least);
        load[least] += weights[i];
    }
    return owner;
}

}  // namespace svetlo
