#!/usr/bin/env bash
# The acceptance test of issue 22's catalogue (tests/hard/): runs hard_warps
# with its wrong twins on each seed and asserts
#  (a) every correct case: every row pass or n/a (no FAIL, no ERROR); a row
#      that tested nothing says n/a, not pass; a passing row shows no NaN;
#  (b) every wrong twin: each check its mark names ("wrong twin, caught by
#      CHECK[,CHECK]: ..." in `hard_warps --list`) is a FAIL row (an ERROR
#      does not count: it says the check could not run); "every check": every
#      row that is not n/a is a FAIL;
#  (c) every row's verdict agrees with the lines its check judged
#      (tests/judged/judged_property.py).
# The first seed runs every check; later seeds leave out the exhaustive sweep,
# which does not depend on the seed. Prints each violation with the row's
# message and its rerun command, then a summary; exits 1 if there was any.
# Usage: run_hard.sh HARD_WARPS WORK_DIR [SEED...]   (default seeds: 1 2)
set -uo pipefail
program=$1
work=$2
shift 2
seeds=("$@")
[ ${#seeds[@]} -gt 0 ] || seeds=(1 2)
mkdir -p "$work"

# Twins and the checks meant to catch them, from the listing: "case<TAB>checks".
"$program" --list --include-flawed --color never > "$work/list.txt" || { echo "hard_warps --list failed"; exit 1; }
awk '/^  [^ ]/ { name = $1 }
     /known flaw .*wrong twin, caught by / {
       sub(/.*wrong twin, caught by /, ""); sub(/:.*/, ""); print name "\t" $0 }' "$work/list.txt" > "$work/twins.tsv"
[ -s "$work/twins.tsv" ] || { echo "no wrong twins found in hard_warps --list"; exit 1; }
# The default checks that apply to some case, for the later seeds (all but exhaustive).
seeded_checks=$(awk '/^      checks:/ { sub(/^ *checks:/, ""); gsub(/\([^)]*\)/, ""); for (i = 1; i <= NF; ++i) if ($i != "exhaustive") print $i }' \
                  "$work/list.txt" | sort -u | sed 's/^/--check /' | tr '\n' ' ')

violations=0
violation() {  # TEXT
  echo "VIOLATION: $1"
  violations=$((violations + 1))
}

# The message and rerun command of a (check, case) row that did not pass.
details() {  # TABLE CHECK CASE
  awk -v key="$2 $3:" 'index($0, "  FAIL " key) == 1 || index($0, "  ERROR " key) == 1 { print; getline; print }' "$1"
}

is_twin() { awk -F'\t' -v c="$1" '$1 == c { found = 1 } END { exit !found }' "$work/twins.tsv"; }

check_correct_rows() {  # TABLE
  local table=$1 verdict check case summary
  while read -r verdict check case summary; do
    is_twin "$case" && continue
    case "$verdict" in
      pass)
        [[ "$summary" == "not applicable"* ]] &&
          violation "$case: $check tested nothing and says pass (must be n/a): $summary"
        grep -Eqi '(^|[^a-z])nan([^a-z]|$)' <<< "$summary" && violation "$case: $check passes with NaN figures: $summary"
        ;;
      n/a) ;;
      weak) ;;  # a pass that says it could not see a 5% tilt: not a failure
      *) violation "$case: $check is $verdict on a correct warp"; details "$table" "$check" "$case" ;;
    esac
  done < <(grep -E '^(pass|weak|FAIL|ERROR|n/a) ' "$table")
}

check_twin_rows() {  # TABLE
  local table=$1 twin checks check verdict rows
  while IFS=$'\t' read -r twin checks; do
    rows=$(awk -v c="$twin" '$3 == c && $1 ~ /^(pass|weak|FAIL|ERROR|n\/a)$/' "$table")
    [ -n "$rows" ] || { violation "twin $twin did not run"; continue; }
    if [ "$checks" = "every check" ]; then
      while read -r verdict check _; do
        [ "$verdict" = FAIL ] || [ "$verdict" = n/a ] || violation "twin $twin: $check is $verdict (every check must FAIL)"
      done <<< "$rows"
      continue
    fi
    for check in ${checks//,/ }; do
      verdict=$(awk -v k="$check" '$2 == k { print $1 }' <<< "$rows")
      [ -n "$verdict" ] || { [ "$seed" != "${seeds[0]}" ] || violation "twin $twin: no $check row"; continue; }
      [ "$verdict" = FAIL ] || { violation "twin $twin: $check is $verdict, must be FAIL"; details "$table" "$check" "$twin"; }
    done
  done < "$work/twins.tsv"
}

for seed in "${seeds[@]}"; do
  table="$work/seed$seed.txt"
  extra=""
  [ "$seed" = "${seeds[0]}" ] || extra=$seeded_checks
  echo "== hard_warps --all --include-flawed --seed $seed $extra"
  status=0
  # shellcheck disable=SC2086  # $extra is a list of options
  "$program" --all --include-flawed --seed "$seed" $extra --color never --wide --json "$work/seed$seed.json" > "$table" 2>&1 ||
    status=$?
  if [ "$status" -gt 1 ] || ! grep -Eq '^[0-9]+ checks: ' "$table"; then
    cat "$table"
    violation "seed $seed: the run did not complete (exit $status)"
    continue
  fi
  grep -E '^[0-9]+ checks: ' "$table"
  check_correct_rows "$table"
  check_twin_rows "$table"
  # (c) every row's verdict is what its check's judged lines say (tests/judged/).
  python3 "$(dirname "$0")/../judged/judged_property.py" "$work/seed$seed.json" ||
    violation "seed $seed: rows whose verdict disagrees with their judged lines (above)"
done

twins=$(wc -l < "$work/twins.tsv")
if [ "$violations" -gt 0 ]; then
  echo "hard catalogue: $violations violations over seeds ${seeds[*]} ($twins wrong twins); tables in $work"
  exit 1
fi
echo "hard catalogue: every correct case passed and every wrong twin was caught on seeds ${seeds[*]} ($twins twins)"
