#!/bin/sh
# Fails when the repository leans on files a clone does not have, or cites issue numbers:
#
#  1. a tracked file names a path under ../shared/ or the spec outside the tree (its folder or its
#     case page by name): the case format is docs/cases.md. Tests may read the shared case files
#     (shared/cases), nothing else may;
#  2. a tracked file (code, comments, build files, tests, printed strings, docs) cites an issue by
#     number (the word, an optional "#", digits): say what the code does and why instead;
#  3. a relative link of a tracked markdown file (README.md, docs/*.md, ...) points to a file missing
#     from the repository or outside it, or to a heading (#anchor) its target does not have.
#
# Files come from `git ls-files` when SOURCE_DIR is a git checkout, else from find (build trees,
# .git and the report folder of the README's first command left out). Binary files are skipped.
#
# usage: self_contained.sh SOURCE_DIR
set -u
cd "$1" || exit 2
root=$(pwd -P)
self=tests/lint/self_contained.sh
list=$(mktemp) || exit 2
trap 'rm -f "$list"' EXIT
if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  git ls-files >"$list"
else
  find . -path ./.git -prune -o -path './build*' -prune -o -path ./report -prune -o -type f -print | sed 's|^\./||' >"$list"
fi
# Keep files that exist (a checkout may have deletions not yet committed) and are text.
files=$(while IFS= read -r f; do [ -f "$f" ] && [ "$f" != "$self" ] && printf '%s\n' "$f"; done <"$list")
if [ -z "$files" ]; then
  echo "no files found under $root"
  exit 2
fi
failed=0

# 1. Paths outside the tree. The words are split so that this script does not match itself.
shared='shared''/'
outside="(\.\./)+${shared}|${shared}spec|CASES""\.md"
hits=$(printf '%s\n' "$files" | tr '\n' '\0' | xargs -0 grep -InE "$outside" 2>/dev/null |
       while IFS= read -r hit; do
         case "$hit" in
           # A test may name the shared case files: what is left without them must be clean.
           tests/*) printf '%s\n' "$hit" | sed -E "s#(\.\./)*${shared}cases##g" | grep -qE "$outside" || continue ;;
         esac
         printf '%s\n' "$hit"
       done)
if [ -n "$hits" ]; then
  echo "Paths outside the repository (cite docs/cases.md; only tests may read ${shared}cases):"
  printf '%s\n' "$hits"
  failed=1
fi

# 2. Issue numbers.
pat='(^|[^A-Za-z])[Ii]ss''ues? ?#?[0-9]+'
hits=$(printf '%s\n' "$files" | tr '\n' '\0' | xargs -0 grep -InE "$pat" 2>/dev/null)
if [ -n "$hits" ]; then
  echo "Issue numbers (say what the code does and why, not which issue asked for it):"
  printf '%s\n' "$hits"
  failed=1
fi

# 3. Relative markdown links. Fenced code blocks and inline code are not links.
slugs() {  # the heading anchors of a markdown file, as GitHub makes them, one per line
  awk '/^```/ { fence = !fence; next } !fence && /^#+ / { sub(/^#+ +/, ""); print }' "$1" |
    tr 'A-Z' 'a-z' | sed -e 's/[^a-z0-9 _-]//g' -e 's/ /-/g'
}
links() {  # LINE<TAB>TARGET for every link of a markdown file outside code
  awk '/^```/ { fence = !fence; next }
       !fence {
         line = $0; gsub(/`[^`]*`/, "", line)
         while (match(line, /\]\([^) ]+/)) {
           print NR "\t" substr(line, RSTART + 2, RLENGTH - 2)
           line = substr(line, RSTART + RLENGTH)
         }
       }' "$1"
}
bad=$(printf '%s\n' "$files" | grep -E '\.md$' | while IFS= read -r md; do
  dir=$(dirname "$md")
  links "$md" | while IFS="$(printf '\t')" read -r n target; do
    case "$target" in http://*|https://*|mailto:*) continue ;; esac
    path=${target%%#*}
    frag=
    case "$target" in *'#'*) frag=${target#*#} ;; esac
    if [ -z "$path" ]; then file=$md; else file="$dir/$path"; fi
    real=$(realpath -m "$file")
    case "$real" in
      "$root"|"$root"/*) ;;
      *) echo "$md:$n: $target: outside the repository"; continue ;;
    esac
    if [ ! -e "$real" ]; then echo "$md:$n: $target: no such file"; continue; fi
    if [ -n "$frag" ] && [ -f "$real" ] && [ "${real%.md}" != "$real" ]; then
      slugs "$real" | grep -qxF "$frag" || echo "$md:$n: $target: no heading #$frag in ${real#"$root"/}"
    fi
  done
done)
if [ -n "$bad" ]; then
  echo "Markdown links that do not resolve inside a clone:"
  printf '%s\n' "$bad"
  failed=1
fi

if [ "$failed" -ne 0 ]; then exit 1; fi
echo "$(printf '%s\n' "$files" | wc -l) files: no path outside the repository, no issue number, every relative markdown link resolves"
