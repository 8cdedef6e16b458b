#!/usr/bin/env python3
"""Runs warpfem on mutated copies of the shipped example configs.

Every mutation is drawn from a seeded generator, so a (seed, index) pair always
gives the same config. Each run must end with exit code 0 or 1 within the time
limit (never a signal, a timeout or another code), and a refusal (exit 1) must
print one "error:" message that names where the problem is: a JSON pointer
(/mesh/refinements), a line of the file (invalid JSON, duplicate key) or the
file itself. The summary also counts refusals that name the mutated field (or
a field inside or around it).

  mutate_configs.py --app build/apps/warpfem --count 1000 [--seed 1] [--jobs 2]
                    [--timeout 60] [--keep DIR]

Exit status 1 if any run failed these rules; the failing configs are kept in
--keep (default: a temporary folder, printed).
"""

import argparse
import concurrent.futures
import json
import os
import random
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

# (command, config) pairs: the shipped examples that run in about a second.
BASES = [
    ("run", "examples/poisson_lshape.json"),
    ("run", "examples/block_compression.json"),
    ("run", "examples/default.json"),
    ("map", "examples/maps/square_to_dart.json"),
    ("map", "examples/maps/star_to_bent_star.json"),
    ("map", "examples/maps/harmonic_square_to_dart.json"),
    ("warp-image", "examples/warp_gear.json"),
]


class Raw:
    """A number written exactly as given (e.g. 1e999, beyond double range)."""

    def __init__(self, text):
        self.text = text


class Obj(list):
    """A JSON object as a list of [key, value] pairs (keeps order, allows duplicates)."""


def strip_comments(text):
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if c == '"':
            j = i + 1
            while j < n and text[j] != '"':
                j += 2 if text[j] == "\\" else 1
            out.append(text[i : j + 1])
            i = j + 1
        elif text.startswith("//", i):
            while i < n and text[i] != "\n":
                i += 1
        elif text.startswith("/*", i):
            end = text.find("*/", i + 2)
            i = n if end < 0 else end + 2
        else:
            out.append(c)
            i += 1
    return "".join(out)


def load(path):
    return json.loads(strip_comments(path.read_text()), object_pairs_hook=lambda pairs: Obj([list(p) for p in pairs]))


def dump(v, indent=0):
    pad = "  " * (indent + 1)
    if isinstance(v, Obj):
        if not v:
            return "{}"
        items = [pad + json.dumps(k) + ": " + dump(x, indent + 1) for k, x in v]
        return "{\n" + ",\n".join(items) + "\n" + "  " * indent + "}"
    if isinstance(v, list):
        return "[" + ", ".join(dump(x, indent + 1) for x in v) + "]"
    if isinstance(v, Raw):
        return v.text
    if isinstance(v, float) and (v != v or v in (float("inf"), float("-inf"))):
        return "1e999"
    return json.dumps(v, ensure_ascii=False)


def nodes(v, pointer=""):
    """Every value with its JSON pointer and a handle (container, index) to replace it."""
    out = []
    if isinstance(v, Obj):
        for i, (k, x) in enumerate(v):
            p = pointer + "/" + k
            out.append((p, v, i))
            out += nodes(x, p)
    elif isinstance(v, list):
        for i, x in enumerate(v):
            p = pointer + "/" + str(i)
            out.append((p, v, i))
            out += nodes(x, p)
    return out


def get(container, i):
    return container[i][1] if isinstance(container, Obj) else container[i]


def put(container, i, value):
    if isinstance(container, Obj):
        container[i][1] = value
    else:
        container[i] = value


EXTREME_NUMBERS = [0, -0.0, -1, 1, 2, 0.5, 1e-9, 1e-300, 5e-324, 1e9, 1e308, -1e308, 2147483647, 2147483648,
                   -2147483649, 9223372036854775807, 9223372036854775808, 18446744073709551616, 1e19, 123456789012,
                   Raw("1e999"), Raw("-1e999"), Raw("1E400"), Raw("-0")]
ODD_STRINGS = ["", " ", "x=3", "1,2", "sin(", "1/0", "0/0", "sqrt(-1)", "x^1e9", "nan", "inf", "-inf", "pi*" * 50,
               "../../../../etc/passwd", "/", ".", "/dev/null", "no_such_file.txt", "Ω∂é中文", "\u0000", "\t\n",
               "a" * 100000, "${HOME}", "'; touch INJECTED; echo '", "-ksp_type", "true", "null", "[1, 2]"]
TYPE_VALUES = ["text", 1, 0.5, True, False, None, [], Obj(), [1, 2], Obj([["a", 1]]), [[0, 0], [1, 0]]]
UNKNOWN_KEYS = ["refinement", "foo", "", "Type", "map ", "source\u0000", "__proto__", "k" * 300]


def random_string(rng):
    alphabet = "abcxyz019 _-+*/^()[]{},.:;'\"\\\n\tΩé\u00ff"
    return "".join(rng.choice(alphabet) for _ in range(rng.randint(1, 40)))


def typo(rng, key):
    if not key:
        return "x"
    i = rng.randrange(len(key))
    op = rng.randrange(4)
    if op == 0:
        return key[:i] + key[i + 1 :]
    if op == 1:
        return key[:i] + rng.choice("abcdefghijklmnopqrstuvwxyz_") + key[i:]
    if op == 2 and len(key) > 1:
        j = min(i + 1, len(key) - 1)
        return key[:i] + key[j] + key[i] + key[j + 1 :] if j != i else key + "s"
    return key.upper()


def mutate_tree(rng, tree):
    """Applies one structural mutation; returns (description, pointer)."""
    all_nodes = nodes(tree)
    # Every field is equally likely, whatever the length of the arrays it sits in
    # (polygons would otherwise draw almost every mutation).
    groups = {}
    for n in all_nodes:
        groups.setdefault(re.sub(r"/\d+", "/*", n[0]), []).append(n)
    pointer, container, i = rng.choice(groups[rng.choice(sorted(groups))])
    value = get(container, i)
    op = rng.choice(["drop", "drop", "duplicate", "type", "type", "number", "number", "number", "string",
                     "string", "rename", "unknown", "wrap", "empty", "reverse", "repeat"])
    if op == "drop":
        del container[i]
        return "drop", pointer
    if op == "duplicate" and isinstance(container, Obj):
        k = container[i][0]
        dup = value if rng.random() < 0.5 else rng.choice(TYPE_VALUES)
        container.insert(i + 1, [k, dup])
        return "duplicate key", pointer
    if op == "rename" and isinstance(container, Obj):
        container[i][0] = typo(rng, container[i][0])
        return "rename key", pointer
    if op == "unknown":
        objects = [(p, c, j) for p, c, j in all_nodes if isinstance(get(c, j), Obj)] or [("", None, None)]
        p, c, j = rng.choice(objects)
        target = tree if c is None else get(c, j)
        target.append([rng.choice(UNKNOWN_KEYS), rng.choice(TYPE_VALUES)])
        return "unknown key", p
    if op == "number":
        put(container, i, rng.choice(EXTREME_NUMBERS))
        return "extreme number", pointer
    if op == "string":
        put(container, i, rng.choice(ODD_STRINGS) if rng.random() < 0.6 else random_string(rng))
        return "string", pointer
    if op == "wrap":
        put(container, i, [value] if rng.random() < 0.5 else Obj([["value", value]]))
        return "wrap", pointer
    if op == "empty" and isinstance(value, (list, Obj)):
        put(container, i, Obj() if isinstance(value, Obj) else [])
        return "empty", pointer
    if op == "reverse" and isinstance(value, list) and not isinstance(value, Obj):
        put(container, i, list(reversed(value)))
        return "reverse", pointer
    if op == "repeat" and isinstance(container, list) and not isinstance(container, Obj):
        container.insert(i, value)
        return "repeat element", pointer
    put(container, i, rng.choice([v for v in TYPE_VALUES if type(v) is not type(value)]))
    return "change type", pointer


def mutate_text(rng, text):
    op = rng.randrange(3)
    i = rng.randrange(len(text))
    if op == 0:
        return "truncate", text[:i]
    if op == 1:
        return "delete char", text[:i] + text[i + 1 :]
    return "insert char", text[:i] + rng.choice('{}[],:"\\x0\n') + text[i:]


def make_case(seed, index):
    rng = random.Random(f"{seed}:{index}")
    command, base = BASES[index % len(BASES)]
    tree = load(ROOT / base)
    what = []
    if rng.random() < 0.1:
        kind, text = mutate_text(rng, dump(tree))
        return command, base, text, [(kind, "")]
    for _ in range(1 if rng.random() < 0.7 else rng.randint(2, 3)):
        if not nodes(tree):
            break
        what.append(mutate_tree(rng, tree))
    return command, base, dump(tree), what


def run_case(args, seed, index, keep):
    command, base, text, what = make_case(seed, index)
    work = Path(tempfile.mkdtemp(prefix=f"mutant-{index}-", dir=args.work))
    (work / "images").symlink_to(ROOT / "examples" / "images")
    config = work / "config.json"
    config.write_text(text)
    out = work / "out"
    if command == "run":
        argv = [args.app, "run", str(config), "--output-dir", str(out)]
    elif command == "map":
        argv = [args.app, "map", "--config", str(config), "--output-dir", str(out)]
    else:
        argv = [args.app, "warp-image", "--config", str(config), "--output", str(out / "warped.png")]
    start = time.monotonic()
    try:
        p = subprocess.run(argv, stdin=subprocess.DEVNULL, capture_output=True, timeout=args.timeout, cwd=work)
        code, err = p.returncode, p.stderr.decode("utf-8", "replace")
    except subprocess.TimeoutExpired:
        code, err = "timeout", ""
    seconds = time.monotonic() - start
    problem = ""
    named_mutated = False
    if code == "timeout":
        problem = f"no result within {args.timeout} s"
    elif code not in (0, 1):
        problem = f"exit code {code}" + (" (signal)" if code < 0 or code > 128 else "")
    elif code == 1:
        errors = [line for line in err.splitlines() if line.startswith("error:")]
        if len(errors) != 1:
            problem = f"{len(errors)} 'error:' lines"
        elif "internal error" in errors[0]:
            problem = "internal error"
        else:
            # After "error: <config>: " comes the place: a JSON pointer or a line of the
            # file; a message about another file (polygon file, image) starts with that file.
            prefix = f"error: {config}: "
            rest = errors[0][len(prefix) :] if errors[0].startswith(prefix) else None
            if rest is None and not re.match(r"error: \S+: ", errors[0]):
                problem = "the message names no file"
            elif rest is not None and not rest.startswith("/") and not re.search(r"\bline \d+", rest):
                problem = "the message names no field or line"
            elif rest is not None and rest.startswith("/"):
                pointer = rest.split(":", 1)[0]
                named_mutated = any(pointer.startswith(m) or m.startswith(pointer) for _, m in what if m)
    if problem and keep:
        shutil.copy(config, Path(keep) / f"mutant-{seed}-{index}.json")
    shutil.rmtree(work, ignore_errors=True)
    return {"index": index, "command": command, "base": base, "what": what, "code": code, "seconds": seconds,
            "problem": problem, "named_mutated": named_mutated, "stderr": err[-2000:]}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--app", required=True)
    ap.add_argument("--count", type=int, default=1000)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--timeout", type=float, default=60)
    ap.add_argument("--keep", default="")
    ap.add_argument("--work", default="")
    ap.add_argument("--report", default="", help="write every result as JSON lines here")
    args = ap.parse_args()
    args.app = str(Path(args.app).resolve())
    tmp = tempfile.mkdtemp(prefix="warpfem-mutants-")
    args.work = args.work or tmp
    keep = args.keep or os.path.join(tmp, "failed")
    os.makedirs(keep, exist_ok=True)
    started = time.monotonic()
    results = []
    report = open(args.report, "w") if args.report else None
    with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
        futures = [pool.submit(run_case, args, args.seed, i, keep) for i in range(args.count)]
        for future in concurrent.futures.as_completed(futures):
            results.append(future.result())
            if report:  # as they come, so an interrupted run still leaves its results
                report.write(json.dumps(results[-1], default=str) + "\n")
                report.flush()
    if report:
        report.close()
    results.sort(key=lambda r: r["index"])
    ok = sum(r["code"] == 0 for r in results)
    refused = sum(r["code"] == 1 for r in results)
    named = sum(r["named_mutated"] for r in results)
    failed = [r for r in results if r["problem"]]
    slowest = max(results, key=lambda r: r["seconds"])
    print(f"mutate_configs: {len(results)} mutated configs (seed {args.seed}): {ok} ran (exit 0), {refused} refused "
          f"(exit 1; {named} name the mutated field or one inside or around it), {len(failed)} failed; "
          f"slowest run {slowest['seconds']:.1f} s (#{slowest['index']}), total {time.monotonic() - started:.0f} s")
    for r in failed:
        print(f"  FAILED #{r['index']} {r['command']} {r['base']} {r['what']}: {r['problem']}")
        tail = r["stderr"].strip().splitlines()[-3:]
        for line in tail:
            print(f"      {line[:300]}")
    if failed:
        print(f"mutate_configs: failing configs kept in {keep}")
    else:
        shutil.rmtree(tmp, ignore_errors=True)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
