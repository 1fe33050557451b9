# The start every frames study shares (frames_time_step.sh,
# frames_sensitivity.sh, frames_damping.sh): sourced, not run, as
#   source "$(dirname "$0")/frames_study_prologue.sh" NAME USAGE "$@"
# It answers --help with USAGE, refuses any argument (the studies take none:
# anything given is a mistake, not a request), moves to the repository root,
# checks the build, and sets `app` (the framequake binary) and `work` (a
# temporary folder removed on exit); validation/results/ exists afterwards.
fq_study_name=$1 fq_study_usage=$2
shift 2
case ${1:-} in -h|--help) echo "$fq_study_usage"; exit 0 ;; esac
[[ $# -eq 0 ]] || { echo "$fq_study_name.sh: no arguments expected, got: $*" >&2; echo "$fq_study_usage" >&2; exit 2; }
cd "$(dirname "${BASH_SOURCE[0]}")/.."
app=./build/apps/framequake
[[ -x $app ]] || { echo "build first: bash scripts/build.sh" >&2; exit 2; }
work=$(mktemp -d "/tmp/fq_${fq_study_name}_XXXXXX")
trap 'rm -rf "$work"' EXIT
mkdir -p validation/results
