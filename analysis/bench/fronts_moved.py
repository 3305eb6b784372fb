#!/usr/bin/env python3
"""fronts_moved.py: what the changes to the search since a commit moved in make results' fronts.

  python3 analysis/bench/fronts_moved.py OLD_COMMIT [--seeds AB.csv] > results/search/moved/section.html

For each committed search front, the best error at cost <= c of the front
at OLD_COMMIT (git show) and of the one in the work tree (named by HEAD's
commit when it is HEAD's), for every cost c
either front has a member at: better, worse or the same (within 0.1 %).
Rows are read by column name (name, cost, error); the catalog's rows are not
members of the search's front and are left out. Writes a page section
(brdfkit report's section rules: tables and text only). --seeds adds the
tallies of fronts_ab.py --csv (the same searches at several seeds, old and new
binaries), read by column name: what one seed's moves are worth.
"""
import csv
import html
import io
import subprocess
import sys

SEARCHES = ["vf2d", "vf", "env", "env_f0", "env_mix", "f_glass", "f_gold"]


def rows(text):
    body = "\n".join(l for l in text.splitlines() if not l.startswith("#"))
    return list(csv.DictReader(io.StringIO(body)))


def front(rs):
    best = {}
    for r in rs:
        if not (r["name"].startswith("search_") or r["name"].startswith("seed_")) or r["error"] == "":
            continue
        c, e = float(r["cost"]), float(r["error"])
        best[c] = min(e, best.get(c, float("inf")))
    return best


def upto(f, c):
    v = [e for k, e in f.items() if k <= c]
    return min(v) if v else None


def verdict(old, new):
    """better, worse or same: new's best error against old's, 0.1 % either way"""
    return "better" if new < old * 0.999 else "worse" if new > old * 1.001 else "same"


def seeds_table(path):
    with open(path, newline="") as f:
        lines = f.readlines()
    said = " ".join(l[1:].strip() for l in lines if l.startswith("#"))  # fronts_ab.py's provenance
    rs = list(csv.DictReader(l for l in lines if not l.startswith("#")))
    seeds = []
    for r in rs:
        if r["seed"] != "all" and r["seed"] not in seeds:
            seeds.append(r["seed"])
    out = ["<p>The same seven searches at seeds %s, two binaries side by side (named below; their "
           "commit may be older than the fronts above): "
           "cost levels better / worse / the same, and the geometric mean of after/before over them "
           "(below 1: better). <code>%s</code></p>" % (html.escape(", ".join(seeds)), html.escape(said)), "<table>",
           "<tr><th>search</th>%s<th>all seeds</th></tr>" % "".join("<th>seed %s</th>" % html.escape(s) for s in seeds)]
    cell = lambda r: "%s / %s / %s, x%s" % tuple(html.escape(r[k]) for k in ("better", "worse", "same", "gmean_new_over_old"))
    for n in SEARCHES + ["all"]:
        by = {r["seed"]: r for r in rs if r["search"] == n}
        if not by:
            continue
        tds = "".join("<td>%s</td>" % (cell(by[s]) if s in by else "") for s in seeds)
        out.append("<tr><td>%s</td>%s<td>%s</td></tr>" % (html.escape(n), tds, cell(by["all"]) if "all" in by else ""))
    out.append("</table>")
    return out


def main():
    args = sys.argv[1:]
    seeds = None
    if len(args) == 3 and args[1] == "--seeds":
        seeds = args[2]
    elif len(args) != 1:
        sys.exit("usage: fronts_moved.py OLD_COMMIT [--seeds AB.csv]")
    old_commit = args[0]
    # "after" is the work tree's fronts: named by the commit that holds them
    # when they are committed, else as the work tree on that commit
    head = subprocess.run(["git", "rev-parse", "--short=8", "HEAD"], capture_output=True, text=True,
                          check=True).stdout.strip()
    clean = subprocess.run(["git", "diff", "--quiet", "HEAD", "--"] +
                           ["results/search/%s/front.csv" % n for n in SEARCHES]).returncode == 0
    after = ("as committed at %s" % head) if clean else ("the work tree's, on commit %s" % head)
    out = ['<section id="search-moved">',
           "<h2>What the search's changes since commit %s moved in the fronts</h2>" % html.escape(old_commit),
           "<p>Best error at cost &lt;= c of each committed search front before (commit %s) and after (%s), "
           "same commands, budgets and seeds. The search is stochastic at a fixed budget: a change to "
           "canonical texts, starts or generation, or to the last bit of a function its fits evaluate, "
           "reorders what it tries, so fronts move both ways (earlier changes: git log of this file's "
           "output, results/search/moved/section.html). "
           "<code>python3 analysis/bench/fronts_moved.py %s%s</code></p>"
           % (html.escape(old_commit), html.escape(after), html.escape(old_commit),
              html.escape(" --seeds " + seeds if seeds else ""))]
    if seeds:
        out.extend(seeds_table(seeds))
    for n in SEARCHES:
        old = subprocess.run(["git", "show", "%s:results/search/%s/front.csv" % (old_commit, n)],
                             capture_output=True, text=True, check=True).stdout
        with open("results/search/%s/front.csv" % n) as f:
            new = f.read()
        fo, fn = front(rows(old)), front(rows(new))
        tally = {"better": 0, "worse": 0, "same": 0}
        lines = []
        for c in sorted(set(fo) | set(fn)):
            a, b = upto(fo, c), upto(fn, c)
            if a is None or b is None:
                v = ""
            else:
                v = verdict(a, b)
                tally[v] += 1
            fmt = lambda x: "" if x is None else "%.4g" % x
            lines.append("<tr><td>%g</td><td>%s</td><td>%s</td><td>%s</td></tr>" % (c, fmt(a), fmt(b), v))
        out.append("<p><code>%s</code>: %d cost levels better, %d worse, %d the same</p>" %
                   (n, tally["better"], tally["worse"], tally["same"]))
        out.append("<table>")
        out.append("<tr><th>cost &lt;=</th><th>before</th><th>after</th><th></th></tr>")
        out.extend(lines)
        out.append("</table>")
    out.append("</section>")
    print("\n".join(out))


if __name__ == "__main__":
    main()
