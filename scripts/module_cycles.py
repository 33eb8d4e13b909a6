#!/usr/bin/env python3
"""No import circle among a crate's top-level modules (issue 34): for each
crate source folder given, the graph of which top-level module refers to
which -- through `crate::X` paths (`use crate::{X, ...}` included), `super::`
paths that reach the crate root, and items the root re-exports (`pub use
m::{A, B}` in lib.rs, mapped back to `m`) -- and its strongly connected
components (Tarjan). Exits 1, listing each circle and its edges, when a
component has more than one module. A text scan, not a compiler's: it reads
paths as written, comments stripped.

    scripts/module_cycles.py compare/src integrator-core/src ... [-v]

A folder may also be a module's (`jobs/src/cloth`, its root `mod.rs`), whose
files refer to one another through `super::`.
"""
import os, re, sys


def check(root):
    mods = {}
    for f in os.listdir(root):
        p = os.path.join(root, f)
        if f.endswith('.rs') and f not in ('lib.rs', 'main.rs', 'mod.rs'):
            mods[f[:-3]] = [p]
        elif os.path.isdir(p):
            files = []
            for dp, _, fs in os.walk(p):
                files += [os.path.join(dp, x) for x in fs if x.endswith('.rs')]
            mods[f] = files
            if os.path.exists(p + '.rs'):
                mods[f].append(p + '.rs')
    names = set(mods)
    def strip_comments(s):
        s = re.sub(r'//[^\n]*', '', s)
        s = re.sub(r'/\*.*?\*/', '', s, flags=re.S)
        return s
    def braces(s, i):
        # s[i] == '{' ; return content up to matching '}'
        d = 0
        for j in range(i, len(s)):
            if s[j] == '{': d += 1
            elif s[j] == '}':
                d -= 1
                if d == 0: return s[i+1:j]
        return s[i+1:]
    def top_items(content):
        # split top-level by commas
        out, d, cur = [], 0, ''
        for ch in content:
            if ch == '{': d += 1
            elif ch == '}': d -= 1
            if ch == ',' and d == 0:
                out.append(cur); cur = ''
            else: cur += ch
        out.append(cur)
        return [x.strip() for x in out if x.strip()]
    graph = {m: set() for m in names}
    for m, files in mods.items():
        for f in files:
            s = strip_comments(open(f).read())
            # crate::X
            for mm in re.finditer(r'\bcrate\s*::\s*(\{|[A-Za-z_]\w*)', s):
                if mm.group(1) == '{':
                    for it in top_items(braces(s, mm.end(1) - 1)):
                        n = re.match(r'[A-Za-z_]\w*', it)
                        if n: graph[m].add(n.group(0))
                else:
                    graph[m].add(mm.group(1))
            # super::X from a file one level below the top (root/m/x.rs): super == crate::m; super::super == crate
            rel = os.path.relpath(f, root).split(os.sep)
            depth = len(rel) - 1  # 0 for top-level files
            if f.endswith('mod.rs'): depth -= 1
            for mm in re.finditer(r'\b((?:super\s*::\s*)+)(\{|[A-Za-z_]\w*)', s):
                ups = mm.group(1).count('super')
                if ups >= depth + 1 and depth >= 0:
                    # reaches crate root
                    if mm.group(2) == '{':
                        for it in top_items(braces(s, mm.end(2) - 1)):
                            n = re.match(r'[A-Za-z_]\w*', it)
                            if n: graph[m].add(n.group(0))
                    else:
                        graph[m].add(mm.group(2))
    # root re-exports: crate::Name where Name is re-exported from lib.rs -> map to its module
    top = next(os.path.join(root, f) for f in ('lib.rs', 'main.rs', 'mod.rs')
               if os.path.exists(os.path.join(root, f)))
    lib = strip_comments(open(top).read())
    reexp = {}
    for mm in re.finditer(r'pub\s+use\s+(\w+)\s*::\s*(\{[^}]*\}|[\w:]+)\s*;', lib):
        mod = mm.group(1); body = mm.group(2)
        items = re.findall(r'\b([A-Za-z_]\w*)\b', body.strip('{}'))
        for it in items: reexp.setdefault(it, mod)
    for m in graph:
        new = set()
        for x in graph[m]:
            if x in names: new.add(x)
            elif x in reexp and reexp[x] in names: new.add(reexp[x])
        new.discard(m)
        graph[m] = new
    # Tarjan
    idx, low, st, on, comps, c = {}, {}, [], set(), [], [0]
    sys.setrecursionlimit(10000)
    def sc(v):
        idx[v] = low[v] = c[0]; c[0] += 1; st.append(v); on.add(v)
        for w in sorted(graph[v]):
            if w not in idx: sc(w); low[v] = min(low[v], low[w])
            elif w in on: low[v] = min(low[v], idx[w])
        if low[v] == idx[v]:
            comp = []
            while True:
                w = st.pop(); on.discard(w); comp.append(w)
                if w == v: break
            comps.append(sorted(comp))
    for v in sorted(graph):
        if v not in idx: sc(v)
    big = [x for x in comps if len(x) > 1]
    print(f"{root}: {len(names)} modules, {sum(len(v) for v in graph.values())} edges, circles: {len([x for x in comps if len(x) > 1])}")
    if '-v' in sys.argv:
        for m in sorted(graph): print(f"  {m} -> {', '.join(sorted(graph[m]))}")
    for comp in big:
        print(f"  [{len(comp)}] {', '.join(comp)}")
        for v in comp:
            print(f"      {v} -> {', '.join(sorted(w for w in graph[v] if w in comp))}")
    return len(big)


if __name__ == "__main__":
    roots = [a for a in sys.argv[1:] if not a.startswith("-")]
    if not roots:
        sys.exit(__doc__)
    sys.exit(1 if sum(check(r) for r in roots) else 0)
