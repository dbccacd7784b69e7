#!/usr/bin/env bash
# The README's list of documents (issue 48, finding 3): every Markdown file
# beside what it describes (board/, src/, tests/, tools/), its title, and
# each of its chapters (## and ###) as a link, read from the headings
# instead of typed, so a chapter moved out of the README stays one click away:
#   readme-docs.sh                      print the block
#   readme-docs.sh --write README.md    replace the marked block
#   readme-docs.sh --check README.md    exit 1 (with a diff) when it differs
#   readme-docs.sh --anchors FILE       the anchors FILE's headings get
# An anchor is GitHub's: the heading in lower case, everything but letters,
# digits, spaces, - and _ dropped, spaces made -, and -1, -2 after repeats.
# `make readme-docs` writes; tests/e2e/test_readme_docs.sh checks.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
export LC_ALL=C
usage() { echo "usage: $0 [--write|--check README | --anchors FILE]" >&2; exit 64; }
[[ $# == 0 || ($# == 2 && ($1 == --write || $1 == --check || $1 == --anchors)) ]] || usage

# headings FILE: "LEVEL<TAB>TEXT<TAB>ANCHOR" for each heading outside code fences.
headings() {
    awk '
        /^```/ { fenced = !fenced; next }
        fenced || !/^#+ / { next }
        {
            level = index($0, " ") - 1
            text = substr($0, level + 2)
            anchor = tolower(text)
            gsub(/[^a-z0-9 _-]/, "", anchor)
            gsub(/ /, "-", anchor)
            if (anchor in seen) { seen[anchor]++; anchor = anchor "-" seen[anchor] } else seen[anchor] = 0
            printf "%d\t%s\t%s\n", level, text, anchor
        }' "$1"
}

if [[ ${1:-} == --anchors ]]; then
    [[ -r $2 ]] || { echo "readme-docs: $2: cannot read it" >&2; exit 66; }
    headings "$2" | cut -f3
    exit 0
fi

block() {
    local doc title links
    echo '| document | chapters |'
    echo '|---|---|'
    while IFS= read -r doc; do
        title=$(headings "$doc" | awk -F'\t' '$1 == 1 { print $2; exit }')
        [[ -n $title ]] || { echo "readme-docs: $doc: no title (a first-level heading)" >&2; exit 65; }
        links=$(headings "$doc" | awk -F'\t' -v doc="$doc" '
            $1 == 2 || $1 == 3 { printf "%s[%s](%s#%s)", (n++ ? (($1 == 2) ? "; " : ", ") : ""), $2, doc, $3 }')
        echo "| [$title]($doc) | ${links:-(one chapter)} |"
    done < <(find board src tests tools -name '*.md' -not -path '*/third_party/*' | sort)
}

if [[ $# == 0 ]]; then
    block
    exit 0
fi
mode=$1 readme=$2
work=$(mktemp -d /tmp/uwbd-readme-docs-XXXXXX)
trap 'rm -rf "$work"' EXIT
block > "$work/block"
awk -v name=readme-docs -v file="$work/block" '
    index($0, "<!-- " name ": begin") == 1 { print; while ((getline line < file) > 0) print line; skip = 1; found++; next }
    index($0, "<!-- " name ": end -->") == 1 { skip = 0 }
    !skip { print }
    END { if (found != 1) { print "readme-docs: marker <!-- " name ": begin --> not found once" > "/dev/stderr"; exit 1 } }' \
    "$readme" > "$work/readme"
if [[ $mode == --write ]]; then
    if ! cmp -s "$work/readme" "$readme"; then
        # Beside the README, then renamed: never half a README.
        cp "$work/readme" "$readme.tmp.$$" && mv "$readme.tmp.$$" "$readme"
    fi
    echo "readme-docs: $readme: $(($(wc -l < "$work/block") - 2)) documents"
elif ! diff -u "$readme" "$work/readme" >&2; then
    echo "readme-docs: $readme's list of documents is not what their headings say (above); run make readme-docs" >&2
    exit 1
fi
