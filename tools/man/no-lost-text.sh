#!/usr/bin/env bash
# Renders each manual page with groff, as man(1) would, and checks that no
# text of its roff source is lost on the way: the words of the source (less
# comment lines, request names and escapes) must be the words of the
# rendered page (less its header and footer line), in the same order. A
# `\"` inside a line starts a comment in roff and silently drops the rest of
# that line; groff does not warn about it, so it is also refused by name.
# Prints one line per page; exits 1 if any page lost text.
#
# Usage: tools/man/no-lost-text.sh PAGE... (roff source, or .gz)
set -uo pipefail
export LC_ALL=C

if [[ $# == 0 ]]; then
    echo "usage: $0 PAGE..." >&2
    exit 64
fi
command -v groff > /dev/null || { echo "$0: groff is not installed (package groff-base)" >&2; exit 69; }

source_of() { if [[ $1 == *.gz ]]; then zcat -- "$1"; else cat -- "$1"; fi; }

# The words a reader should see: comment lines, .TH (it makes the header and
# footer), requests that print nothing, scdoc's preamble (.ie/.el/.ds), the
# troff (.el) branch of scdoc's lists and the indents of .IP/.TP/.RS dropped;
# font changes and motions (\h'..' around a list's bullet) removed, special
# characters and non-printing escapes made separators. \" is left as a quote: what the author meant.
words_of_source() {
    sed -E -e '/^[.'\''][[:space:]]*\\"/d' -e '/^\.TH( |$)/d' \
        -e '/^\.el \\\{\\$/,/^\.\\\}$/d' -e '/^\.(ie|el|ds)( |$)/d' -e '/^\.\\\}$/d' \
        -e 's/^\.(TP|PP|LP|P|br|sp|nf|fi|EX|EE|RS|RE|ad|na|nh|hy|in|ne)( .*)?$//' \
        -e 's/^\.IP ("[^"]*"|[^ ]*).*$/\1/' \
        -e 's/^\.[A-Za-z]+ ?//' \
        -e 's/\\\\/ /g' \
        -e 's/\\f(\[[^]]*\]|\(..|.)//g' \
        -e 's/\\\(..|\\\[[^]]*\]/ /g' \
        -e 's/\\[hv]'\''[^'\'']*'\''//g' -e 's/\\[&|^%c]//g' |
        tr -cs 'A-Za-z0-9' '\n' | sed '/^$/d'
}

# What groff prints (no hyphenation, so no word is split), less the first and
# last non-empty lines: the header and footer made from .TH.
words_rendered() {
    groff -man -Tutf8 -rHY=0 -P-cbou 2> /dev/null |
        sed '/^[[:space:]]*$/d' | sed '1d;$d' |
        tr -cs 'A-Za-z0-9' '\n' | sed '/^$/d'
}

lost=0
for page in "$@"; do
    name=$(basename "$page")
    # \\ is a printed backslash; any other \" outside a comment line is a comment.
    bad=$(source_of "$page" | grep -nv '^[.'\''][[:space:]]*\\"' | sed 's/\\\\//g' | grep -F '\"' | head -3)
    if [[ -n $bad ]]; then
        echo "$name: \\\" starts a roff comment and drops the rest of the line (write \\(dq): $bad"
        lost=1
        continue
    fi
    src=$(source_of "$page" | words_of_source)
    out=$(source_of "$page" | words_rendered)
    if [[ -z $out ]]; then
        echo "$name: groff renders nothing"
        lost=1
    elif [[ $src != "$out" ]]; then
        first=$(diff <(echo "$src") <(echo "$out") | head -6 | tr '\n' ' ')
        echo "$name: the rendered page differs from its source's text (diff source rendered: $first)"
        lost=1
    else
        echo "$name: $(wc -l <<< "$src") words rendered, none lost"
    fi
done
exit "$lost"
