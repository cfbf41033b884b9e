#!/usr/bin/env python3
# Writes shaders/tile_windows.glsl: the tile resolve's sorted register windows, written out slot by
# slot (GLSL has no loops a CPU driver would unroll into registers; see that file's top comment).
# Run from the repository root after changing a size: python3 shaders/tile_windows.py
PENDING, OPEN = 16, 32


def insert(name, n, arrays, keys):
    body = ["{"]
    for a, k in zip(arrays, keys):
        body.append(f"    {'uint' if a.endswith('s') else 'float'} {k} = {k.upper()};")
    cs = [f"bool c{i} = {keys[0]} < {arrays[0]}[{i}];" for i in range(n)]
    for i in range(0, n, 4):
        body.append("    " + " ".join(cs[i:i + 4]))
    for i in range(n - 1, -1, -1):
        parts = []
        for a, k in zip(arrays, keys):
            if i > 0:
                parts.append(f"{a}[{i}] = c{i - 1} ? {a}[{i - 1}] : (c{i} ? {k} : {a}[{i}]);")
            else:
                parts.append(f"{a}[0] = c0 ? {k} : {a}[0];")
        body.append("    " + " ".join(parts))
    body.append("}")
    return f"#define {name}(" + ", ".join(k.upper() for k in keys) + ") \\\n" + " \\\n".join(body) + "\n"


def shift(name, n, arrays):
    body = ["{"]
    for a in arrays:
        body.append("    " + " ".join(f"{a}[{i}] = {a}[{i + 1}];" for i in range(n - 1)))
    body.append(f"    {arrays[0]}[{n - 1}] = NO_T;")
    body.append("}")
    return f"#define {name} \\\n" + " \\\n".join(body) + "\n"


def clear(name, n, a):
    return f"#define {name} " + " = ".join(f"{a}[{i}]" for i in range(n)) + " = NO_T;\n"


HEADER = """// The tile resolve's two sorted windows, held in registers (every index a literal constant: a
// dynamically indexed local array becomes per-lane scratch memory on a CPU device; docs/performance.md).
// Written by shaders/tile_windows.py, slot by slot for these sizes.
//
//   pending entries: pt[TILE_PENDING] (entry distance, the key), pe[] (its exit), ps[] (its sphere)
//   open exits:      xt[TILE_OPEN] (exit distance, the key), xs[] (its sphere)
//
// Empty slots hold NO_T, which sorts after every distance, so they gather at the end. Equal
// distances keep their arrival order: a zero-length segment lies between them, so the order
// changes nothing but rounding.
#ifndef BRUME_TILE_WINDOWS_GLSL
#define BRUME_TILE_WINDOWS_GLSL

"""

out = [HEADER, f"const uint TILE_PENDING = {PENDING}u;\nconst uint TILE_OPEN = {OPEN}u;\nconst float NO_T = 3.4e38;\n\n",
       clear("TILE_PENDING_CLEAR", PENDING, "pt"), clear("TILE_OPEN_CLEAR", OPEN, "xt"),
       "\n// Inserts an event in order (with c_i = (key < slot i): slot i takes its left neighbour if c_(i-1),\n"
       "// else the key if c_i, else keeps its own); a key past the last slot falls off the end.\n",
       insert("TILE_PENDING_INSERT", PENDING, ["pt", "pe", "ps"], ["k_t", "k_e", "k_s"]),
       insert("TILE_OPEN_INSERT", OPEN, ["xt", "xs"], ["k_t", "k_s"]),
       "\n// Drops slot 0 and moves every slot one place left.\n",
       shift("TILE_PENDING_SHIFT_LEFT", PENDING, ["pt", "pe", "ps"]),
       shift("TILE_OPEN_SHIFT_LEFT", OPEN, ["xt", "xs"]), "\n#endif\n"]
with open("shaders/tile_windows.glsl", "w") as f:
    f.write("".join(out))
