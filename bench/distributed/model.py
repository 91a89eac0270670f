"""Time to image on many ranks, predicted from what one machine measures (docs/distributed.md).

svetlo's MPI render (apps/svetlo/distributed.cpp) hands out tiles from rank 0, which also
renders between them, and gathers each tile's pixels there. Its time to image on N ranks is
bounded by four things, each computed here from measured inputs:

  compute   the work shared out: work / N, plus the last tile (the tail)
  setup     what every rank does alone before its first tile: read the scene, build the BVH;
            for the hierarchical radiosity solve, the whole solve (it is replicated)
  gather    rank 0's link: every tile's bytes come in through it (one 10 Gb/s NIC)
  service   rank 0 answers requests and pastes tiles between tiles of its own: one tile's
            service costs t_serve, and all N - 1 workers must be served in each of its tiles

The prediction is setup + max(compute, gather, service); the script names the bound that
decides at each N, and what would move it.

The progressive radiosity solve is split among the ranks by patches (each rank makes its
patches' leaves' part of every row) and exchanges the patches' unshot light after every shot.
Its time is the larger share of the work (a patch is not split, so past as many ranks as
patches nothing divides), plus one all-gather per shot (log2 N message latencies and the
patches' bytes through each rank's link), plus the leaves' light gathered once at the end.

    python3 bench/distributed/model.py            # the figures of docs/distributed.md
"""

# Measured on the 2-core machine of docs/distributed.md: render seconds at -np 1 -t 1, tiles of
# 32 x 32 pixels at 12 bytes a pixel. Radiosity's solve (33,681 elements) is the whole of its
# render there: -np 2 took as long (0.743 s against 0.721 s), so it is setup here. The 4K case
# scales the Cornell box's cost per sample. Not measured, assumed: rank 0's service of one
# tile (a receive of 12 KiB over shared memory or a NIC, its paste, an answer) at 20 us, and
# a message's latency at 20 us.
CASES = {
    "whitted 960x540 16 spp": dict(work=5.43, tiles=510, tile_bytes=32 * 32 * 12, setup=0.003),
    "path Cornell 512x512 64 spp": dict(work=24.98, tiles=256, tile_bytes=32 * 32 * 12, setup=0.003),
    "path 4K (3840x2160) 1024 spp": dict(work=24.98 * (3840 * 2160 / 512**2) * 16, tiles=8100,
                                         tile_bytes=32 * 32 * 12, setup=0.003),
    "radiosity hierarchical, 33,681 elements": dict(work=0.02, tiles=8,
                                                      tile_bytes=256 * 32 * 12, setup=0.72),
}
# The progressive solve of the Cornell box with 55,296 elements (docs/distributed.md): its
# render seconds at -np 1 -t 1, shots, patches, and the leaves (whose light, 48 bytes each, is
# gathered at the end).
SOLVES = {
    "radiosity progressive, 55,296 elements": dict(work=8.46, shots=1575, patches=216,
                                                   leaves=55296),
    "radiosity progressive, 1M elements (scaled)": dict(work=8.46 * 1e6 / 55296, shots=1575,
                                                        patches=216, leaves=1000000),
}
LINK = 10e9 / 8       # bytes per second into rank 0 (10 Gb/s)
LATENCY = 20e-6       # seconds a message takes, end to end
T_SERVE = 20e-6       # rank 0's time per tile served (receive, paste, answer)


def predict(case, ranks):
    per_tile = case["work"] / case["tiles"]
    # Dynamic balance: the work divides, plus one tile of tail; with fewer than a few tiles
    # per rank, the tiles themselves are the bound (some ranks wait with nothing to take).
    compute = case["work"] / ranks
    tiles = per_tile * max(1.0, ranks / case["tiles"]) + per_tile
    gather = case["tiles"] * case["tile_bytes"] / LINK + case["tiles"] * LATENCY / ranks
    service = case["tiles"] * T_SERVE                    # all of it on rank 0
    bounds = {"compute": compute + per_tile, "tiles": tiles if case["tiles"] < 4 * ranks else 0,
              "gather": gather, "service": service}
    bound = max(bounds, key=bounds.get)
    return case["setup"] + bounds[bound], bound


def predict_solve(case, ranks):
    import math
    compute = case["work"] / min(ranks, case["patches"])
    steps = math.ceil(math.log2(ranks)) if ranks > 1 else 0
    exchange = case["shots"] * (steps * LATENCY + case["patches"] * 24 / LINK) if ranks > 1 else 0
    final = case["leaves"] * 48 / LINK if ranks > 1 else 0
    bound = ("patches" if ranks > case["patches"] else
             "exchange" if exchange > compute else "compute")
    return compute + exchange + final, bound


def main():
    moves = {
        "compute": "more ranks (the work still divides)",
        "tiles": "smaller tiles (fewer than four a rank leaves ranks idle)",
        "gather": "a tree reduce, or ranks that write their own tiles",
        "service": "a rank 0 that only serves, or ranks that take tiles by a shared counter",
        "setup": "distributing the solve itself (the hierarchical one; the progressive one is split)",
    }
    for name, case in CASES.items():
        print(name)
        one, _ = predict(case, 1)
        for ranks in (1, 2, 8, 64, 512):
            t, bound = predict(case, ranks)
            if case["setup"] > t - case["setup"]:
                bound = "setup"
            print("  %4d ranks: %9.3f s, %7.1f x, bound by %s" % (ranks, t, one / t, bound))
        print("  past that: %s" % moves[bound])
    solve_moves = {
        "compute": "more ranks, up to one a patch",
        "exchange": "fewer exchanges: several shooters a round (shooting the k brightest "
                    "patches at once), or a tree of ranks that only sends what changed",
        "patches": "smaller patches, or splitting a patch's leaves among ranks (then its "
                   "sums need a fixed order of their own)",
    }
    for name, case in SOLVES.items():
        print(name)
        one, _ = predict_solve(case, 1)
        for ranks in (1, 2, 8, 64, 512):
            t, bound = predict_solve(case, ranks)
            print("  %4d ranks: %9.3f s, %7.1f x, bound by %s" % (ranks, t, one / t, bound))
        print("  past that: %s" % solve_moves[bound])


if __name__ == "__main__":
    main()
