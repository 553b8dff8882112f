"""A property-based campaign of tops on a floor: random valid runs, each checked for the
properties of ``tests/floor_properties.py`` (no part below the floor, no missed touchdown, no
energy from nowhere, finite states, an allowed status, contact flags on the floor).

    python tests/fuzz/floor_campaign.py --runs 10000 --seed 1 --timeout 20

Case ``i`` of seed ``s`` is drawn from ``numpy.random.default_rng([s, i])``, so any case can
be drawn again alone (``--only i``). The cases run one after another in a worker process
(never more than one at a time) under a memory limit (``RLIMIT_AS``, ``--memory-gib``, 4 GiB
by default: a runaway allocation ends the worker, not the machine) and a time limit per case.
The runner restarts the worker after a crash or a hang. Each case ends in one outcome:

- ``ok``: a trajectory with every property;
- ``refused``: a kreisel error that refuses the run and says what to change (the pace
  guard, the step cap): acceptable, counted by message;
- ``violation``: a property violated (counted by kind), or any other exception (``error``,
  ``panic``);
- ``timeout``: no answer within ``--timeout`` s: a hang, or a run far slower than its motion
  needs. Each is probed again to a tenth of ``t_end``: the probe's steps and seconds tell a
  slow run (many steps) from one that stalls;
- ``crash``: the worker died (a segfault, an abort, the memory limit), with its last words.

The counts go to stdout, with up to ``--examples`` reproducers (Python one-liners) per kind,
each shrunk (``--shrink``: parts, rates, laws and losses removed while the violation of that
kind stays; numbers rounded) to a smaller case of the same violation. Every failing case
goes to ``--out`` (JSON). The extension the worker loaded (its file's modification time) is
recorded per case: another developer may rebuild it during a campaign.
"""

from __future__ import annotations

import argparse
import collections
import copy
import json
import os
import select
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))  # tests/: floor_properties

import floor_properties as fp  # noqa: E402

OUTCOMES = ("ok", "refused", "violation", "timeout", "crash")
BAD = ("violation", "timeout", "crash")


# --------------------------------------------------------------------------------------
# the worker
# --------------------------------------------------------------------------------------


def _limit_memory(gib: float) -> None:
    import resource

    limit = int(gib * 2**30)
    resource.setrlimit(resource.RLIMIT_AS, (limit, limit))


def _build_stamp() -> str:
    """The loaded extension's file and modification time."""
    import kreisel._core as core

    st = os.stat(core.__file__)
    return (
        f"{os.path.basename(core.__file__)} {time.strftime('%H:%M:%S', time.gmtime(st.st_mtime))}"
    )


def worker(seed: int, jobs: list, t_end: float, rtol, gib: float) -> None:
    """Runs ``jobs`` (``[key, spec]``: the spec given, or None to draw case ``key`` of
    ``seed``): a line ``S key <spec>`` before each run and ``E key <result>`` after it."""
    import warnings

    import numpy as np

    _limit_memory(gib)
    warnings.simplefilter("error")
    out = os.fdopen(1, "w", buffering=1)
    stamp = _build_stamp()
    for key, given in jobs:
        t0 = time.monotonic()
        try:
            if given is None:
                case = fp.random_floor_case(np.random.default_rng([seed, key]))
            else:
                case = fp.build(given)
                case["construction_refusals"] = []
        except BaseException as e:  # noqa: BLE001 - a panic while building is a finding
            if isinstance(e, KeyboardInterrupt):
                raise
            out.write(f"S {key} " + json.dumps({"spec": given, "build": stamp}) + "\n")
            msg = f"error: building the case: {type(e).__name__}: {e}"[:600]
            out.write(f"E {key} " + json.dumps({"verdict": "violation", "details": [msg]}) + "\n")
            continue
        head = {
            "spec": case["spec"],
            "construction_refusals": case["construction_refusals"],
            "build": stamp,
        }
        out.write(f"S {key} " + json.dumps(head) + "\n")
        result = fp.run_case(case, t_end, rtol)
        try:
            verdict, details = fp.outcome(case, result)
        except Exception as e:  # noqa: BLE001 - a fault of the checks, told apart
            verdict, details = "violation", [f"checker_error: {type(e).__name__}: {e}"[:600]]
        rec = {"verdict": verdict, "details": details, "seconds": time.monotonic() - t0}
        if not isinstance(result, BaseException):
            rec.update(
                rows=len(result.t), status=result.status, steps=int(result.stats.get("steps", -1))
            )
        del result
        out.write(f"E {key} " + json.dumps(rec) + "\n")


# --------------------------------------------------------------------------------------
# the runner
# --------------------------------------------------------------------------------------


def run(
    seed: int, jobs, *, t_end: float, rtol=None, timeout: float = 20.0, gib: float = 4.0, log=None
) -> dict:
    """Runs ``jobs`` (case indices to draw, or ``(key, spec)`` pairs) in worker processes,
    one at a time: ``{key: record}``, each with ``verdict``, ``details``, ``spec`` (the
    worker's ``S`` line: the spec, the refusals met drawing it, the build) and, where known,
    ``seconds``, ``rows``, ``steps`` and ``status``."""
    todo = [[j, None] if isinstance(j, int) else [j[0], j[1]] for j in jobs]
    results: dict = {}
    env = {**os.environ, "RUST_BACKTRACE": "0", "MPLBACKEND": "Agg"}
    while todo:
        fd, listing = tempfile.mkstemp(suffix=".json")
        with os.fdopen(fd, "w") as fh:
            json.dump(todo, fh)
        err = tempfile.TemporaryFile()
        proc = subprocess.Popen(
            [
                sys.executable,
                os.path.abspath(__file__),
                "--worker",
                str(seed),
                listing,
                repr(t_end),
                repr(rtol),
                repr(gib),
            ],
            stdout=subprocess.PIPE,
            stderr=err,
            env=env,
        )
        try:
            done = _follow(proc, results, timeout, err, log)
        finally:
            proc.stdout.close()
            if proc.poll() is None:
                proc.kill()
            proc.wait()
            err.close()
            os.unlink(listing)
        todo = [j for j in todo if j[0] not in results and j[0] not in done]
    return results


def _follow(proc, results, timeout, err, log) -> set:
    """Reads a worker's lines until it ends or hangs; the keys it finished or failed."""
    buf = b""
    current, since, head = None, time.monotonic(), None
    done: set = set()
    fd = proc.stdout.fileno()
    while True:
        wait = max(0.0, timeout - (time.monotonic() - since)) if current is not None else 600
        ready, _, _ = select.select([fd], [], [], wait)
        if not ready:
            proc.kill()
            proc.wait()
            if current is None:
                raise RuntimeError("the worker printed nothing for 600 s")
            results[current] = {
                "verdict": "timeout",
                "spec": head,
                "seconds": timeout,
                "details": [f"timeout: no answer within {timeout} s"],
            }
            done.add(current)
            return done
        chunk = os.read(fd, 1 << 16)
        if not chunk:
            rc = proc.wait()
            err.seek(0)
            words = err.read().decode(errors="replace").strip()
            if current is None and not done:
                raise RuntimeError(f"the worker exited with {rc} before any case:\n{words[-2000:]}")
            if current is not None and current not in results:
                tail = " | ".join(words.splitlines()[-3:])[-500:]
                results[current] = {
                    "verdict": "crash",
                    "spec": head,
                    "details": [f"crash: worker exited with {rc}: {tail}"],
                }
                done.add(current)
            return done
        buf += chunk
        *lines, buf = buf.split(b"\n")
        for line in lines:
            kind, _, rest = line.decode().partition(" ")
            key, _, payload = rest.partition(" ")
            key = int(key) if key.lstrip("-").isdigit() else key
            if kind == "S":
                current, since, head = key, time.monotonic(), json.loads(payload)
            elif kind == "E":
                rec = json.loads(payload)
                rec["spec"] = head
                results[key] = rec
                done.add(key)
                if log is not None and len(results) % 100 == 0:
                    log(f"  {len(results)} cases")


def probe(seed, results, *, t_end, rtol, timeout, gib, fraction):
    """Runs each timed-out case again to ``fraction * t_end``: the steps, rows and seconds
    there tell a slow run (many steps, time in proportion) from one that stalls."""
    late = [
        (i, r["spec"]["spec"])
        for i, r in sorted(results.items())
        if r["verdict"] == "timeout" and r.get("spec") and r["spec"].get("spec")
    ]
    if not late:
        return {}
    return run(seed, late, t_end=t_end * fraction, rtol=rtol, timeout=timeout, gib=gib)


# --------------------------------------------------------------------------------------
# shrinking a failing case
# --------------------------------------------------------------------------------------


def _signature(rec, kind) -> bool:
    """Whether a run's record shows a violation of ``kind`` (for ``error``: the same kind of
    error, by its first words)."""
    if rec["verdict"] != "violation":
        return False
    if ":" in kind:  # error: <Type>: <first words>
        return any(error_kind(d) == kind for d in rec["details"])
    return kind in {fp.kind_of(d) for d in rec["details"]}


def error_kind(detail: str) -> str:
    """``error: NumericalError: numerical failure: play top, slip mode: step size too`` ...:
    an error's kind by its type and first words (numbers dropped)."""
    return " ".join(fp.refusal_key(detail).split()[:8])


def _valid(spec) -> bool:
    t = spec["top"]
    if t["form"] == "classic":
        return True
    parts = t["parts"]
    return max(fp._lateral(p) for p in parts) >= 1e-3 and fp._hull_margin(parts) >= 0.0


def _round(x):
    return float(f"{x:.3g}") if isinstance(x, float) and x != 0.0 else x


def _candidates(spec):
    """Simpler specs than ``spec``: one part fewer, no friction or a plain law, no losses,
    one rate or velocity set to 0, the numbers rounded to 3 digits."""
    t, s = spec["top"], spec["state"]
    out = []

    def variant(fn):
        c = copy.deepcopy(spec)
        fn(c)
        if c != spec and _valid(c):
            out.append(c)

    if t["form"] == "parts":
        for k in range(len(t["parts"])):
            if len(t["parts"]) > 1:
                variant(lambda c, k=k: c["top"]["parts"].pop(k))
    variant(lambda c: c["top"].update(friction=["Frictionless"]))
    if t["friction"][0] == "CoulombContensou":
        variant(lambda c: c["top"].update(friction=["Coulomb", t["friction"][1]]))
    for k in ("restitution", "rolling_resistance", "drilling_resistance"):
        variant(lambda c, k=k: c["top"].update({k: 0.0}))
    if s["form"] == "euler":
        for k in ("theta_dot", "phi_dot", "psi_dot", "vx", "vy", "phi", "psi"):
            variant(lambda c, k=k: c["state"].update({k: 0.0}))
        if s["height"] is not None:
            variant(lambda c: c["state"].update(height=None))
            variant(lambda c: c["state"].update(height=0.0))
        variant(lambda c: c["state"].update({k: _round(v) for k, v in s.items()}))
    else:
        for k in ("omega", "com_velocity"):
            for i in range(3):
                variant(lambda c, k=k, i=i: c["state"][k].__setitem__(i, 0.0))
        variant(lambda c: c["state"]["com"].__setitem__(0, 0.0))
        variant(
            lambda c: c["state"].update(
                omega=[_round(x) for x in s["omega"]],
                com_velocity=[_round(x) for x in s["com_velocity"]],
            )
        )

    def round_top(c):
        top = c["top"]
        for k in (
            "m",
            "A",
            "C",
            "s",
            "rho",
            "restitution",
            "rolling_resistance",
            "drilling_resistance",
        ):
            if k in top:
                top[k] = _round(top[k])
        if top["C"] > 2 * top["A"]:
            top["C"] = 2 * top["A"]
        top["friction"] = [top["friction"][0]] + [_round(x) for x in top["friction"][1:]]
        if "parts" in top:
            top["parts"] = [[p[0]] + [_round(x) for x in p[1:]] for p in top["parts"]]

    if s["form"] == "euler":  # an explicit state's G sits on the unrounded parts
        variant(round_top)
    return out


def shrink(spec, kind, *, seed, t_end, rtol, timeout, gib, rounds=12):
    """A smaller spec with a violation of ``kind`` (greedy: each round runs every candidate
    of :func:`_candidates` in one worker and keeps the first that still shows it); None if
    ``spec`` itself no longer shows it."""
    again = run(seed, [("c", spec)], t_end=t_end, rtol=rtol, timeout=timeout, gib=gib)
    if not _signature(again.get("c", {"verdict": ""}), kind):
        return None  # not reproduced (the extension may have changed since)
    best = spec
    for _ in range(rounds):
        cands = _candidates(best)
        if not cands:
            break
        recs = run(
            seed,
            [(f"c{j}", c) for j, c in enumerate(cands)],
            t_end=t_end,
            rtol=rtol,
            timeout=timeout,
            gib=gib,
        )
        ok = [j for j in range(len(cands)) if _signature(recs.get(f"c{j}", {"verdict": ""}), kind)]
        if not ok:
            break
        best = cands[ok[0]]
    return best


# --------------------------------------------------------------------------------------
# the report
# --------------------------------------------------------------------------------------


def kinds(rec) -> list[str]:
    """The kinds of a failing record: its violations' kinds (an error by its first words),
    or timeout / crash."""
    if rec["verdict"] in ("timeout", "crash"):
        return [rec["verdict"]]
    out = set()
    for d in rec["details"]:
        k = fp.kind_of(d)
        out.add(error_kind(d) if k in ("error", "panic") else k)
    return sorted(out)


def summarise(
    results,
    *,
    seed,
    t_end,
    rtol,
    probes=None,
    fraction=0.1,
    examples=3,
    shrink_args=None,
    out=sys.stdout,
):
    """Prints the counts and up to ``examples`` reproducers per kind (shrunk if
    ``shrink_args``); returns the JSON record of the failing cases."""
    by = collections.Counter(r["verdict"] for r in results.values())
    refused = collections.Counter(
        fp.refusal_key(r["details"][0]) for r in results.values() if r["verdict"] == "refused"
    )
    per_kind = collections.defaultdict(list)
    for i, r in sorted(results.items()):
        if r["verdict"] in BAD:
            for k in kinds(r):
                per_kind[k].append(i)
    construction = collections.Counter(
        fp.refusal_key(m)
        for r in results.values()
        if r.get("spec")
        for m in r["spec"].get("construction_refusals", [])
    )
    builds = collections.Counter((r.get("spec") or {}).get("build") for r in results.values())
    print(
        f"{len(results)} runs (seed {seed}, t_end {t_end} s, rtol "
        f"{'default' if rtol is None else rtol})",
        file=out,
    )
    print(
        "extension builds loaded: " + ", ".join(f"{b} ({c} runs)" for b, c in builds.items()),
        file=out,
    )
    print("outcomes: " + ", ".join(f"{o} {by.get(o, 0)}" for o in OUTCOMES), file=out)
    if refused:
        print("refused (by message):", file=out)
        for m, c in refused.most_common():
            print(f"  {c:6d}  {m[:300]}", file=out)
    if per_kind:
        print("failing runs by kind (a run may have several kinds):", file=out)
        for k, v in sorted(per_kind.items(), key=lambda kv: -len(kv[1])):
            print(f"  {len(v):6d}  {k}", file=out)
    if construction:
        print("tops kreisel refused while drawing (each redrawn):", file=out)
        for m, c in construction.most_common():
            print(f"  {c:6d}  {m[:300]}", file=out)
    failing = {}
    for i, rec in sorted(results.items()):
        if rec["verdict"] not in BAD:
            continue
        spec = (rec.get("spec") or {}).get("spec")
        entry = {
            "index": i,
            "seed": seed,
            "verdict": rec["verdict"],
            "kinds": kinds(rec),
            "details": rec["details"],
            "seconds": rec.get("seconds"),
            "rows": rec.get("rows"),
            "steps": rec.get("steps"),
            "build": (rec.get("spec") or {}).get("build"),
            "reproducer": fp.reproducer(spec, t_end, rtol) if spec else None,
            "spec": spec,
        }
        if probes and i in probes:
            p = probes[i]
            entry["probe"] = {k: p.get(k) for k in ("verdict", "seconds", "rows", "steps")}
            entry["probe"]["t_end"] = t_end * fraction
        failing[i] = entry
    for k, idx in sorted(per_kind.items(), key=lambda kv: -len(kv[1])):
        print(f"\n[{k}] {len(idx)} runs", file=out)
        for i in idx[:examples]:
            e = failing[i]
            mine = [d for d in e["details"] if k in kinds({"verdict": "", "details": [d]})]
            print(
                f"- case {i}: " + "; ".join(d[:300] for d in (mine or e["details"])[:2]), file=out
            )
            if "probe" in e:
                print(f"  probe to {t_end * fraction:.3g} s: {e['probe']}", file=out)
            print(f"  {e['reproducer']}", file=out)
            if shrink_args is not None and e["spec"] and k not in ("timeout", "crash"):
                small = shrink(e["spec"], k, t_end=t_end, rtol=rtol, **shrink_args)
                if small is None:
                    print("  (not reproduced when shrinking: the extension changed?)", file=out)
                elif small != e["spec"]:
                    e.setdefault("shrunk", {})[k] = fp.reproducer(small, t_end, rtol)
                    print(f"  shrunk: {fp.reproducer(small, t_end, rtol)}", file=out)
            out.flush()
    return list(failing.values())


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--worker", nargs=5, help=argparse.SUPPRESS)
    ap.add_argument("--runs", type=int, default=1000)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--start", type=int, default=0, help="first case index")
    ap.add_argument("--only", type=int, nargs="*", help="run just these case indices")
    ap.add_argument("--t-end", type=float, default=0.3, help="seconds of motion per run")
    ap.add_argument("--rtol", type=float, default=None, help="default: kreisel's")
    ap.add_argument("--timeout", type=float, default=20.0, help="seconds per run")
    ap.add_argument("--memory-gib", type=float, default=4.0, help="RLIMIT_AS of the worker")
    ap.add_argument(
        "--probe-fraction",
        type=float,
        default=0.1,
        help="probe the timeouts to this fraction of t_end (0: no probe)",
    )
    ap.add_argument("--examples", type=int, default=3, help="reproducers printed per kind")
    ap.add_argument("--shrink", action="store_true", help="shrink the printed reproducers")
    ap.add_argument("--out", default="floor_campaign_failures.json")
    ap.add_argument(
        "--no-pull",
        action="store_true",
        help="leave out the pull property (floor_properties.check_run (g))",
    )
    args = ap.parse_args(argv)
    if args.no_pull:
        os.environ["KREISEL_CHECK_PULL"] = "0"
    if args.worker:
        seed, listing, t_end, rtol, gib = args.worker
        with open(listing) as fh:
            jobs = json.load(fh)
        worker(int(seed), jobs, float(t_end), None if rtol == "None" else float(rtol), float(gib))
        return 0
    indices = args.only if args.only else list(range(args.start, args.start + args.runs))
    t0 = time.monotonic()

    def log(m):
        print(f"{m} ({time.monotonic() - t0:.0f} s)", file=sys.stderr, flush=True)

    common = {"rtol": args.rtol, "timeout": args.timeout, "gib": args.memory_gib}
    results = run(args.seed, indices, t_end=args.t_end, log=log, **common)
    probes = None
    if args.probe_fraction > 0:
        log("probing the timeouts")
        probes = probe(args.seed, results, t_end=args.t_end, fraction=args.probe_fraction, **common)
    shrink_args = None
    if args.shrink:
        shrink_args = {
            "seed": args.seed,
            "timeout": min(args.timeout, 10.0),
            "gib": args.memory_gib,
        }
    failing = summarise(
        results,
        seed=args.seed,
        t_end=args.t_end,
        rtol=args.rtol,
        probes=probes,
        fraction=args.probe_fraction,
        examples=args.examples,
        shrink_args=shrink_args,
    )
    with open(args.out, "w") as fh:
        json.dump(
            {
                "seed": args.seed,
                "t_end": args.t_end,
                "rtol": args.rtol,
                "counts": dict(collections.Counter(r["verdict"] for r in results.values())),
                "failing": failing,
                "refused": {
                    str(i): r["details"][0][:300]
                    for i, r in sorted(results.items())
                    if r["verdict"] == "refused"
                },
            },
            fh,
            indent=1,
        )
    log(f"{len(failing)} failing cases written to {args.out}")
    return 1 if failing else 0


if __name__ == "__main__":
    sys.exit(main())
