#!/usr/bin/env python3
"""Seeded mutants of glTF models run through the command line (docs/robustness.md, "Mutants of real files").

    tests/tools/mutants.py RESTITCH_BINARY OUT_DIR MODEL.glb [MODEL.glb ...] [--per-model N] [--seed S]

For each model, N mutants (default 40; seeded, so the same run gives the same files): bit flips,
truncation, absurd accessor counts and offsets, broken node matrices (NaN, zero, huge), a missing
or doubled BIN chunk, a JSON chunk cut short. Each mutant is run through `restitch info` and
`restitch resize --steps 1`. Passes when every run ends with a documented exit code (0, 3, 4 or 5;
6 and 7 cannot happen here), a non-empty message on stderr whenever it is not 0, no crash (a
signal), and no output file (or temporary file) left by a failed resize. Prints one line per
failure and a summary; exits 1 on any failure."""
import json, os, random, struct, subprocess, sys

def chunks(glb):
    if glb[:4] != b"glTF" or len(glb) < 20:
        return None
    n = struct.unpack_from("<I", glb, 12)[0]
    js = glb[20:20 + n]
    rest = glb[20 + n:]
    return js, rest

def assemble(js, rest):
    js = js + b" " * (-len(js) % 4)
    body = struct.pack("<II", len(js), 0x4E4F534A) + js + rest
    return struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body

def mutate(glb, rng, kind):
    data = bytearray(glb)
    if kind == "bitflip":
        for _ in range(rng.randint(1, 16)):
            i = rng.randrange(len(data))
            data[i] ^= 1 << rng.randrange(8)
        return bytes(data)
    if kind == "truncate":
        return bytes(data[:rng.randrange(1, len(data))])
    parts = chunks(glb)
    if parts is None:
        return bytes(data)
    js, rest = parts
    try:
        doc = json.loads(js)
    except ValueError:
        return bytes(data)
    if kind == "count" and doc.get("accessors"):
        a = rng.choice(doc["accessors"])
        a["count"] = rng.choice([0, 1, 2**31, 2**31 - 1, 2**32 + 3, 10**9, a.get("count", 1) * 1000])
    elif kind == "offset" and doc.get("accessors"):
        a = rng.choice(doc["accessors"])
        a["byteOffset"] = rng.choice([2**31, 2**32 - 4, 10**12, -8, 3])
        if doc.get("bufferViews"):
            v = rng.choice(doc["bufferViews"])
            v[rng.choice(["byteOffset", "byteLength", "byteStride"])] = rng.choice([0, 1, 2**31, 10**12, 255])
    elif kind == "matrix":
        node = {"mesh": 0, "matrix": [rng.choice([0.0, 1e300, -1e300, 1.0, float("nan")]) for _ in range(16)]}
        doc.setdefault("nodes", []).append(node)
        doc.setdefault("scenes", [{"nodes": []}])[0].setdefault("nodes", []).append(len(doc["nodes"]) - 1)
        text = json.dumps(doc).replace("NaN", "nan" if rng.random() < 0.5 else "NaN")
        return assemble(text.encode(), rest)
    elif kind == "nochunk":
        return assemble(json.dumps(doc).encode(), b"")
    elif kind == "twochunks":
        return assemble(json.dumps(doc).encode(), rest + rest)
    elif kind == "cutjson":
        text = json.dumps(doc).encode()
        return assemble(text[:rng.randrange(1, len(text))], rest)
    return assemble(json.dumps(doc).encode(), rest)

KINDS = ["bitflip", "truncate", "count", "offset", "matrix", "nochunk", "twochunks", "cutjson"]

def main(argv):
    args, per_model, seed = [], 40, 1
    i = 0
    while i < len(argv):
        if argv[i] == "--per-model": per_model = int(argv[i + 1]); i += 2
        elif argv[i] == "--seed": seed = int(argv[i + 1]); i += 2
        else: args.append(argv[i]); i += 1
    if len(args) < 3:
        print(__doc__); return 2
    binary, out, models = args[0], args[1], args[2:]
    os.makedirs(out, exist_ok=True)
    failures, runs, codes = [], 0, {}
    for model in models:
        glb = open(model, "rb").read()
        rng = random.Random(f"{seed}:{os.path.basename(model)}")
        for k in range(per_model):
            kind = KINDS[k % len(KINDS)]
            path = os.path.join(out, f"{os.path.basename(model)}.{k:03d}.{kind}.glb")
            open(path, "wb").write(mutate(glb, rng, kind))
            result = path + ".out.glb"
            for cmd in ([binary, "info", path], [binary, "resize", path, "-o", result, "--steps", "1"]):
                runs += 1
                try:
                    p = subprocess.run(cmd, capture_output=True, timeout=600)
                    code, err = p.returncode, p.stderr.decode(errors="replace").strip()
                except subprocess.TimeoutExpired:
                    code, err = "timeout", ""
                codes[code] = codes.get(code, 0) + 1
                what = f"{os.path.basename(path)} {cmd[1]}"
                if code not in (0, 3, 4, 5):
                    failures.append(f"{what}: exit {code} {err[-300:]}")
                elif code != 0 and not err:
                    failures.append(f"{what}: exit {code} without a message")
                if cmd[1] == "resize" and code != 0:
                    left = [f for f in os.listdir(out) if f.startswith(os.path.basename(result))]
                    if left:
                        failures.append(f"{what}: exit {code} left {left}")
            if os.path.exists(result):
                os.remove(result)
    for f in failures:
        print("FAIL", f)
    print(f"{runs} runs of {len(models) * per_model} mutants: exit codes {dict(sorted(codes.items(), key=str))}; "
          f"{len(failures)} failures")
    return 1 if failures else 0

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
