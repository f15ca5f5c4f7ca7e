#!/usr/bin/env python3
"""Speed-up of a render on many MPI processes, simulated from measured tile costs.

Usage: simulate_scaling.py --message-us M [--ranks 8,64,512] NAME=COSTS.csv ...

COSTS.csv is what `lobe_bench_tiles SCENE --csv` writes: one line per tile (x0, y0, x1, y1,
seconds on one worker thread). M is the seconds (in µs) a process other than rank 0 waits for
each tile it is handed (`mpirun -n 2 lobe_bench_tiles --message-cost`).

Each rank is one worker. Two ways to share an image's tiles are compared:
- static: rank i renders the rows [floor(i·H/P), floor((i+1)·H/P)) — what `--shard i/P` does;
  a tile's cost is spread evenly over its rows;
- dynamic: what `mpirun lobe render` does (core/cluster.h). Workers ask rank 0 for the next tile
  in row order whenever they finish one; rank 0's own worker takes it at no cost, the others wait
  M for the answer, and rank 0 answers one request at a time, each taking it M as well (a
  pessimistic bound: the measured M is a whole round trip). With --chunk k a request fetches k
  consecutive tiles (k = 1 is what lobe does today).
Speed-up = sum of tile costs / the time the last worker finishes; efficiency = speed-up / P. Scene
loading (every rank loads in parallel) and the final gather of pixels are left out.
"""
import argparse
import csv
import heapq


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


def dynamic_makespan(tiles, ranks, message, chunk):
    costs = [c for _, _, c in tiles]
    work = [sum(costs[i:i + chunk]) for i in range(0, len(costs), chunk)]
    # Workers in the order they ask: (time of the request, rank).
    asking = [(0.0, r) for r in range(ranks)]
    heapq.heapify(asking)
    server_free = 0.0
    finish = 0.0
    for w in work:
        t, rank = heapq.heappop(asking)
        if rank == 0:
            start = t
        else:
            served = max(t, server_free)
            server_free = served + message
            start = served + message
        end = start + w
        finish = max(finish, end)
        heapq.heappush(asking, (end, rank))
    return finish


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--message-us", type=float, required=True)
    ap.add_argument("--ranks", default="8,64,512")
    ap.add_argument("workloads", nargs="+", help="NAME=COSTS.csv")
    args = ap.parse_args()
    message = args.message_us * 1e-6
    ranks = [int(r) for r in args.ranks.split(",")]
    print("| workload | tiles | tile cost mean / max (ms) | ranks | static rows: speed-up (eff.) "
          "| dynamic, 1 tile a request | dynamic, 4 tiles a request |")
    print("|---|---|---|---|---|---|---|")
    for item in args.workloads:
        name, path = item.split("=", 1)
        tiles = read_costs(path)
        total = sum(c for _, _, c in tiles)
        mean_ms = 1e3 * total / len(tiles)
        max_ms = 1e3 * max(c for _, _, c in tiles)
        for p in ranks:
            cells = []
            for span in (static_makespan(tiles, p), dynamic_makespan(tiles, p, message, 1),
                         dynamic_makespan(tiles, p, message, 4)):
                s = total / span
                cells.append(f"{s:.1f} ({100 * s / p:.0f} %)")
            print(f"| {name} | {len(tiles)} | {mean_ms:.2f} / {max_ms:.1f} | {p} | " +
                  " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
