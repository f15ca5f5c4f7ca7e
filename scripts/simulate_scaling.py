#!/usr/bin/env python3
"""Speed-up of a render on many MPI processes, simulated from measured tile costs.

Usage: simulate_scaling.py --latency-us L --service-us S [--ranks 8,64,512] NAME=COSTS.csv ...

COSTS.csv is what `lobe_bench_tiles SCENE --csv` writes: one line per tile (x0, y0, x1, y1,
seconds on one worker thread). From `mpirun -n 2 lobe_bench_tiles --message-cost`: L is the
round trip of a tile request from another process (its wait for the answer when it has nothing
to render, rank 0's polling included), S the time rank 0 is busy with one request (a request
and its answer between two spinning processes).

Each rank is one worker. Two ways to share an image's tiles are compared:
- static: rank i renders the rows [floor(i·H/P), floor((i+1)·H/P)) — what `--shard i/P` does;
  a tile's cost is spread evenly over its rows;
- dynamic: what `mpirun lobe render` does (cluster/cluster.h). Tiles go out in row order. Rank 0's
  own worker takes its next tile when it finishes one, at no cost; a worker of another rank asks
  for its next tile as it starts one, and the answer comes L later. Rank 0 answers one request at
  a time, S each: the requests queue when they come faster than 1/S.
- guided over a shuffled order (not built; what the table says would come next): the tiles in a
  fixed random order, and each request fetching max(1, remaining / (2·P)) of them (guided
  self-scheduling, Polychronopoulos & Kuck 1987), so that rank 0 answers far fewer requests.
Speed-up = sum of tile costs / the time the last worker finishes; efficiency = speed-up / P. Scene
loading (every rank loads in parallel) and the final gather of pixels are left out.
"""
import argparse
import csv
import heapq
import random


def read_costs(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return [(int(r["y0"]), int(r["y1"]), float(r["seconds"])) for r in rows]


def static_makespan(tiles, ranks):
    height = max(y1 for _, y1, _ in tiles)
    per_row = [0.0] * height
    for y0, y1, cost in tiles:
        for y in range(y0, y1):
            per_row[y] += cost / (y1 - y0)
    bands = [sum(per_row[i * height // ranks:(i + 1) * height // ranks]) for i in range(ranks)]
    return max(bands)


def dynamic_makespan(tiles, ranks, latency, service, chunk):
    """chunk: tiles a request fetches, or 'guided': remaining / (2 · ranks), at least 1."""
    costs = [c for _, _, c in tiles]
    # Requests in the order rank 0 sees them: (time, rank). Rank 0's worker takes its next tile
    # when it finishes one; another rank's worker asks for its next tile when it starts one.
    asking = [(0.0, r) for r in range(ranks)]
    heapq.heapify(asking)
    busy_until = [0.0] * ranks   # when each worker finishes the tile it has
    server_free = 0.0
    finish = 0.0
    taken = 0
    while taken < len(costs):
        n = chunk if chunk != "guided" else max(1, (len(costs) - taken) // (2 * ranks))
        w = sum(costs[taken:taken + n])
        taken += n
        t, rank = heapq.heappop(asking)
        if rank == 0:
            start = max(t, busy_until[0])
            end = start + w
            heapq.heappush(asking, (end, 0))
        else:
            served = max(t, server_free)
            server_free = served + service
            start = max(served + latency, busy_until[rank])
            end = start + w
            heapq.heappush(asking, (start, rank))
        busy_until[rank] = end
        finish = max(finish, end)
    return finish


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--latency-us", type=float, required=True)
    ap.add_argument("--service-us", type=float, required=True)
    ap.add_argument("--ranks", default="8,64,512")
    ap.add_argument("workloads", nargs="+", help="NAME=COSTS.csv")
    args = ap.parse_args()
    latency, service = args.latency_us * 1e-6, args.service_us * 1e-6
    ranks = [int(r) for r in args.ranks.split(",")]
    print("| workload | tiles | tile cost mean / max (ms) | ranks | static rows: speed-up (eff.) "
          "| dynamic as built: speed-up (eff.) | guided, shuffled (not built) |")
    print("|---|---|---|---|---|---|---|")
    for item in args.workloads:
        name, path = item.split("=", 1)
        tiles = read_costs(path)
        total = sum(c for _, _, c in tiles)
        mean_ms = 1e3 * total / len(tiles)
        max_ms = 1e3 * max(c for _, _, c in tiles)
        for p in ranks:
            cells = []
            shuffled = tiles[:]
            random.Random(1).shuffle(shuffled)
            for span in (static_makespan(tiles, p), dynamic_makespan(tiles, p, latency, service, 1),
                         dynamic_makespan(shuffled, p, latency, service, "guided")):
                s = total / span
                cells.append(f"{s:.1f} ({100 * s / p:.0f} %)")
            print(f"| {name} | {len(tiles)} | {mean_ms:.2f} / {max_ms:.1f} | {p} | " +
                  " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
