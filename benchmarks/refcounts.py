"""Find reference counting left inside the compiled CPU loops (a silent 20 % slowdown).

Numba increments and decrements the reference count of an array each time a function that uses
it is entered and left; after inlining, LLVM removes the pairs, except where Numba's pruning pass
cannot prove them redundant: then each neighbour pair of the gather pays two atomic operations on a
shared counter. It happened once in the pair loop (the per-pair `pr2` array after a change of
operation order in `physics.rates`: 20 % of the 3D dam break's step). This script compiles the CPU
kernels of every built-in case's scheme (in a fresh Numba cache: cached code cannot be inspected)
and reports each compiled function with a reference increment inside a loop of its control flow.

    python benchmarks/refcounts.py            # all built-in cases; exit 1 if any is found
    python benchmarks/refcounts.py dam-break-dualsphysics rip-current
    python benchmarks/refcounts.py --default-only rip-current   # without the case's variants
"""

import atexit
import os
import re
import shutil
import sys
import tempfile

import numpy as np

if "NUMBA_CACHE_DIR" not in os.environ:
    os.environ["NUMBA_CACHE_DIR"] = tempfile.mkdtemp(prefix="shoal-refcounts-")
    atexit.register(shutil.rmtree, os.environ["NUMBA_CACHE_DIR"], ignore_errors=True)

# coarse spacings, so that each case is quick to build (its scheme does not depend on dp)
COARSE = {"dam-break-2d": dict(dp=0.02), "dam-break-3d": dict(dp=0.03), "dam-break-dualsphysics": dict(dp=0.03),
          "still-water-2d": {}, "still-water-3d": {}, "wave-flume-2d": {}, "wave-flume-3d": dict(dp=0.05),
          "tidal-bore": dict(dp=0.02), "tidal-bore-piers": dict(dp=0.02), "rip-current": dict(dp=0.075)}
VARIANTS = {"tidal-bore": [dict(dim=2), dict(half=True)], "tidal-bore-piers": [dict(half=True)],
            "rip-current": [dict(boundary="repulsive")]}


def _blocks(body):
    """[(label, text)] of the basic blocks of one LLVM function body."""
    blocks, label, lines = [], "entry", []
    for line in body.splitlines():
        m = re.match(r"^([\w.$-]+):", line)
        if m:
            blocks.append((label, "\n".join(lines)))
            label, lines = m.group(1), []
        else:
            lines.append(line)
    blocks.append((label, "\n".join(lines)))
    return blocks


def _loop_blocks(blocks):
    """Labels of the blocks that lie on a cycle of the control-flow graph (Tarjan's SCCs)."""
    succ = {lab: set(re.findall(r"label %([\w.$-]+)", text)) for lab, text in blocks}
    index, low, stack, on, out = {}, {}, [], set(), set()
    counter = [0]

    def visit(v):
        # iterative Tarjan (functions have thousands of blocks)
        work = [(v, iter(sorted(succ.get(v, ()))))]
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        while work:
            node, it = work[-1]
            for w in it:
                if w not in succ:
                    continue
                if w not in index:
                    index[w] = low[w] = counter[0]
                    counter[0] += 1
                    stack.append(w)
                    on.add(w)
                    work.append((w, iter(sorted(succ[w]))))
                    break
                if w in on:
                    low[node] = min(low[node], index[w])
            else:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[node])
                if low[node] == index[node]:
                    comp = []
                    while True:
                        w = stack.pop()
                        on.discard(w)
                        comp.append(w)
                        if w == node:
                            break
                    if len(comp) > 1 or node in succ[node]:
                        out.update(comp)

    for lab, _ in blocks:
        if lab not in index:
            visit(lab)
    return out


def increfs_in_loops(ir):
    """{function name: [the pointers of the NRT_incref calls inside a loop]} in LLVM IR text `ir`."""
    out = {}
    for m in re.finditer(r"^define [^@]*@(\S+)\(.*?\{\n(.*?)^}", ir, re.M | re.S):
        blocks = _blocks(m.group(2))
        loops = _loop_blocks(blocks)
        count = [p for lab, text in blocks if lab in loops
                 for p in re.findall(r"@NRT_incref\(ptr ([^)]+)\)", text)]
        # the parallel loop's own increments of its arguments, once per particle around the call
        # of the per-particle function (about 1.5 ns each here), are expected
        if count and "numba_parfor_gufunc" not in m.group(1):
            out[re.sub(r"B\d+v\d+B\d+\S*", "", m.group(1))] = count
    return out


def check_case(name, kwargs, seen, label):
    """Build case `name`, evaluate its rates once, and return the increments inside loops of every
    CPU kernel compiled on the way ({kernel: {function: count}}), or the label of the case in
    `seen` ({spec key: label}) with the same scheme."""
    import shoal.cases as cases
    from shoal.runner import build_model

    case = cases.CASES[name](**kwargs)
    m = build_model(case)
    if m.spec.key in seen:
        return seen[m.spec.key]
    seen[m.spec.key] = label
    m.sort()
    m.compute_rates()
    # the other neighbour loops: filters, probes, free surface, wall forces
    m.apply_filter("shepard")
    m.apply_filter("mls")
    xyz = m.world_positions()
    lo, hi = xyz.min(axis=0), xyz.max(axis=0)
    m.sample(np.array([0.5 * (lo + hi)]), shepard=True)
    m.free_surface()
    m.wall_forces()
    found = {}
    b = m.backend
    for attr in sorted(vars(b)):
        k = getattr(b, attr)
        sigs = getattr(k, "signatures", None)
        if not sigs:
            continue
        for sig in sigs:
            rep = increfs_in_loops(k.inspect_llvm(sig))
            if rep:
                found[attr] = rep
    return found


def main(argv):
    default_only = "--default-only" in argv
    argv = [a for a in argv if a != "--default-only"]
    unknown = [a for a in argv if a not in COARSE]
    if unknown:
        print(f"refcounts.py: unknown case {unknown[0]!r}; allowed: {', '.join(COARSE)}", file=sys.stderr)
        return 2
    names = argv or list(COARSE)
    bad = 0
    seen = {}
    for name in names:
        for kw in [{}] + ([] if default_only else VARIANTS.get(name, [])):
            args = dict(COARSE.get(name, {}), **kw)
            label = f"{name} {kw}" if kw else name
            found = check_case(name, args, seen, label)
            if isinstance(found, str):
                # its kernels came from the cache, where they cannot be inspected
                print(f"{label}: the scheme of {found}")
            elif found:
                bad += 1
                for kernel, funcs in found.items():
                    for fn, ptrs in funcs.items():
                        print(f"{label}: kernel {kernel}: {fn[-60:]}: reference increments inside loops "
                              f"({', '.join(ptrs)})")
            else:
                print(f"{label}: no reference counting inside the loops")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
