#!/usr/bin/env python3
"""The exact frame's stages from call stacks: reads `perf script` output of bench/orbit_stages
recorded with --call-graph=dwarf, keeps the samples under ViewSession::render (the frames: not
loading), and gives each to the innermost stage on its stack (issue 46 item 1, option (b)).
Prints one markdown row: the stages' percentages of the frames' samples.
Usage: perf script -i DATA | perf_stages.py MESH"""
import re
import sys

# Innermost match wins: the stack is read from the sampled function outward.
STAGES = [
    ("ray tests", r"ray_qi|ray_test_rest|ray_test_all|RayCaster::|qi_by_ray|libembree"),
    ("walks", r"AppelPropagation::walk\b|walk_to|PathWalk|SegmentGrid::build|occluder_grid"),
    ("propagation + settle", r"assign_qi_appel|AppelPropagation::"),
    ("vertex images + clipping", r"clip_occluders|clip_occluder_range|clip_curves|clip_edge|VertexImages"),
    ("crossing search + cuts", r"build_pieces|build_range|RangeBuild|BoxPairs"),
    ("cusps + chaining", r"chain|cusp|Cusp|Chain"),
    ("finder", r"SilhouetteFinder|ViewSession::find"),
]
ORDER = ["finder", "cusps + chaining", "vertex images + clipping", "crossing search + cuts",
         "propagation + settle", "walks", "ray tests", "other"]

def samples(lines):
    stack = []
    for line in lines:
        if not line.strip():
            if stack:
                yield stack
            stack = []
        elif line.startswith((" ", "\t")):
            stack.append(line.strip())
        else:
            stack = []
    if stack:
        yield stack

def main():
    mesh = sys.argv[1] if len(sys.argv) > 1 else ""
    counts = {k: 0 for k in ORDER}
    total = 0
    for stack in samples(sys.stdin):
        if not any("ViewSession::render" in f for f in stack):
            continue
        total += 1
        stage = "other"
        for frame in stack:  # innermost first
            hit = next((name for name, rx in STAGES if re.search(rx, frame)), None)
            # (VertexImages made on first use by a walk or the propagation count there)
            if hit:
                stage = hit
                if hit == "vertex images + clipping" and "VertexImages" in frame:
                    outer = next((n for f in stack[stack.index(frame) + 1:]
                                  for n, rx in STAGES if re.search(rx, f) and n != hit), None)
                    if outer in ("walks", "propagation + settle", "ray tests"):
                        stage = outer
                break
        counts[stage] += 1
    cells = [f"{100.0 * counts[k] / max(total, 1):.0f}" for k in ORDER]
    print(f"| {mesh} | " + " | ".join(cells) + f" | {total} |")

if __name__ == "__main__":
    main()
