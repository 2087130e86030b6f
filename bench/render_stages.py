#!/usr/bin/env python3
"""Where a whole `inkline render` spends its CPU, stage by stage and thread by thread: reads
`perf script -F comm,pid,tid,ip,sym` output of runs recorded with --call-graph=dwarf (see
bench/run_render_stages.sh) and gives each sample to the first stage whose pattern matches its
stack, read from the sampled function outward (so the innermost stage wins, and the kernel's page
faults count as their own stage wherever they happen). The main thread's samples are the ones
the wall time waits for; the helper threads' (the self-intersection search, a Hilbert sort) run
beside them. Prints a markdown table: ms per run on each thread (samples / frequency / runs).
Usage: perf script ... | render_stages.py FREQUENCY_HZ RUNS"""
import re
import sys

STAGES = [
    ("page faults (first touch of memory)", r"asm_exc_page_fault|exc_page_fault"),
    ("dynamic loader, start-up", r"_dl_start|_dl_relocate|dl_main|_dl_map_object|_dl_init|do_lookup_x|call_init"),
    ("self-intersections", r"self_intersections|SelfIntersections|PairSearch|BoxPairs|faces_intersect|faces_of\b"),
    ("Hilbert order", r"hilbert_ordered|Hilbert_sort"),
    ("topology", r"build_topology"),
    ("parse + repairs", r"load_mesh|repair_mesh|corner_mates"),
    ("features", r"extract_features|SilhouetteFinder|facing"),
    ("visibility", r"build_pieces|assign_qi|compute_visibility|AppelPropagation|VertexImages|RangeBuild|walk_to|RayCaster"),
    ("output (strokes, SVG, file)", r"write_drawing|drawing_to_svg|drawing_strokes|chain_strokes|svg_of"),
    ("freeing memory, exit", r"_int_free|malloc_consolidate|__libc_free|munmap|exit_mmap|zap_page|do_exit"),
    ("exec, process set-up", r"bprm_execve|execve|load_elf_binary"),
]
ORDER = [name for name, _ in STAGES] + ["other"]


def samples(lines):
    head, stack = None, []
    for line in lines:
        if not line.strip():
            if head:
                yield head, stack
            head, stack = None, []
        elif line.startswith((" ", "\t")):
            stack.append(line.strip())
        else:
            head, stack = line, []
    if head:
        yield head, stack


def main():
    hz, runs = float(sys.argv[1]), float(sys.argv[2])
    main_t = {k: 0 for k in ORDER}
    helper = {k: 0 for k in ORDER}
    for head, stack in samples(sys.stdin):
        m = re.match(r"\S+\s+(\d+)/(\d+)", head)
        if not m:
            continue
        text = " | ".join(re.sub(r"^[0-9a-f]+\s+", "", s) for s in stack)
        stage = next((name for name, pattern in STAGES if re.search(pattern, text)), "other")
        (main_t if m.group(1) == m.group(2) else helper)[stage] += 1
    scale = 1000.0 / hz / runs
    print("| stage | main thread ms | helper threads ms |")
    print("|---|---:|---:|")
    for k in ORDER:
        if main_t[k] or helper[k]:
            print(f"| {k} | {main_t[k] * scale:.1f} | {helper[k] * scale:.1f} |")
    print(f"| total | {sum(main_t.values()) * scale:.1f} | {sum(helper.values()) * scale:.1f} |")


if __name__ == "__main__":
    main()
