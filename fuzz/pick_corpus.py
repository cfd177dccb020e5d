#!/usr/bin/env python3
"""Picks a small corpus greedily by edge coverage.

libFuzzer's merge (`cargo fuzz cmin`) keeps every input that adds a feature:
hundreds of files here. The committed corpus, replayed by `cargo test` in a
debug build, should stay at tens of files, so this keeps the K inputs that
each add the most edges not yet covered (ties: smaller file first).

    ./target/x86_64-unknown-linux-gnu/release/batch -merge=1 \
        -merge_control_file=/tmp/batch.ctl /tmp/empty-dir ALL_INPUTS_DIR
    python3 pick_corpus.py /tmp/batch.ctl corpus/batch 80

With `--prefer LIST` (a file of paths, one a line), up to K1 inputs are
first taken from LIST (e.g. JSON that deserialises), then the rest from all:

    python3 pick_corpus.py /tmp/json.ctl corpus/config_json 60 --prefer valid.txt 30
"""
import os
import shutil
import sys


def main() -> None:
    args = sys.argv[1:]
    prefer, k1 = set(), 0
    if "--prefer" in args:
        i = args.index("--prefer")
        prefer = set(open(args[i + 1]).read().split())
        k1 = int(args[i + 2])
        del args[i : i + 3]
    control, out_dir, k = args[0], args[1], int(args[2])
    lines = open(control).read().split("\n")
    n = int(lines[0])
    files = lines[2 : 2 + n]
    cov = {}
    for line in lines[2 + n :]:
        parts = line.split()
        if parts and parts[0] == "COV":
            cov[int(parts[1])] = set(map(int, parts[2:]))
    every = set().union(*cov.values())
    covered, chosen = set(), []

    def pick(candidates, limit):
        while len(chosen) < limit:
            left = [i for i in candidates if i not in chosen]
            if not left:
                return
            best = max(
                left, key=lambda i: (len(cov[i] - covered), -os.path.getsize(files[i]))
            )
            if not cov[best] - covered:
                return
            chosen.append(best)
            covered.update(cov[best])

    pick([i for i in cov if files[i] in prefer], k1)
    pick(list(cov), k)
    size = sum(os.path.getsize(files[i]) for i in chosen)
    print(f"{len(chosen)} files, {size} bytes: {len(covered)} of {len(every)} edges")
    os.makedirs(out_dir, exist_ok=True)
    for i in chosen:
        shutil.copy(files[i], out_dir)


if __name__ == "__main__":
    main()
