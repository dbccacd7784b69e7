#!/usr/bin/env bash
# Sums gcovr's per-file CSV (make coverage) into one line per folder of src/:
# lines and branches covered, and their percentages. With a README path,
# also replaces the block between its "make coverage" markers with the table.
# Usage: tools/coverage/summary.sh FILES.CSV [README.md]
set -euo pipefail
csv="$1"
readme="${2:-}"
[[ -r "$csv" ]] || { echo "coverage summary: $csv: cannot read (run make coverage)" >&2; exit 1; }

# gcovr 5 CSV: filename,line_total,line_covered,line_percent,branch_total,branch_covered,...
table="$(printf "%-16s %15s %8s %17s\n" folder lines "" branches;
    awk -F, 'NR > 1 && $1 ~ /^src\// {
        dir = $1; sub(/\/[^\/]*$/, "", dir)
        lt[dir] += $2; lc[dir] += $3; bt[dir] += $5; bc[dir] += $6
        LT += $2; LC += $3; BT += $5; BC += $6
    }
    function pct(c, t) { return t ? sprintf("%5.1f %%", 100 * c / t) : "    - " }
    function row(name, c, t, bcv, btv) {
        return sprintf("%-16s %6d / %-6d %8s %7d / %-7d %8s", name, c, t, pct(c, t), bcv, btv, pct(bcv, btv))
    }
    END {
        for (d in lt) print row(d, lc[d], lt[d], bc[d], bt[d]) | "sort"
        close("sort")
        print row("src (all)", LC, LT, BC, BT)
    }' "$csv")"
echo "$table"

[[ -n "$readme" ]] || exit 0
begin='<!-- make coverage: begin -->'
end='<!-- make coverage: end -->'
grep -qxF "$begin" "$readme" && grep -qxF "$end" "$readme" ||
    { echo "coverage summary: $readme lacks the lines $begin and $end" >&2; exit 1; }
tmp="$(mktemp "$readme.XXXXXX")"
awk -v begin="$begin" -v end="$end" -v table="$table" '
    $0 == begin { print; print "```"; print table; print "```"; skip = 1; next }
    $0 == end { skip = 0 }
    !skip { print }' "$readme" >"$tmp"
mv "$tmp" "$readme"
echo "coverage summary: table written into $readme"
