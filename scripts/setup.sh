#!/usr/bin/env bash
# One-command set-up of railderail in ./.venv:
#   Python 3.11/3.12 venv, pinned packages (requirements.txt + setup.py, versions from
#   constraints.txt, ROS 2 Jazzy wheels included), railderail_msgs built with CMake into the venv,
#   railderail installed editable, then a check that the messages import and a node starts.
# Idempotent: when nothing it depends on has changed since the last complete run (stamp in .venv),
# it only re-runs the final check. Logs: build/setup-logs/. Choose the interpreter with PYTHON=...
set -euo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
VENV=$ROOT/.venv
VPY=$VENV/bin/python
MSG_BUILD=$ROOT/build/msgs
LOGS=$ROOT/build/setup-logs
STAMP=$VENV/.railderail-setup-stamp
cd "$ROOT"

step_no=0
say() { printf '==> %s\n' "$*"; }
die() { printf 'setup.sh: error: %s\n' "$*" >&2; exit 1; }

# run_step TITLE LOG HINT COMMAND...: run COMMAND with its output in build/setup-logs/LOG;
# on failure say which step failed, show the end of the log and what to do.
run_step() {
    local title=$1 log=$LOGS/$2 hint=$3 start=$SECONDS
    shift 3
    step_no=$((step_no + 1))
    say "[$step_no] $title (log: ${log#"$ROOT"/})"
    if ! "$@" >"$log" 2>&1; then
        {
            printf '\nsetup.sh: step "%s" failed. Last lines of %s:\n' "$title" "${log#"$ROOT"/}"
            grep -v "^WARNING: Location '.*' is ignored" "$log" | tail -n 25 | sed 's/^/    /'
            printf 'What to do: %s\n' "$hint"
        } >&2
        exit 1
    fi
    printf '    done in %d s\n' $((SECONDS - start))
}

# Hash of everything the venv is made from (this script included).
inputs_hash() {
    find scripts/setup.sh requirements.txt constraints.txt setup.py package.xml resource ros2_run \
        msg_defs -type f -print0 | LC_ALL=C sort -z | xargs -0 sha256sum | sha256sum | cut -d' ' -f1
}

check_venv() {
    ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST "$VPY" - <<'EOF'
import rclpy
import railderail_msgs.msg
from railderail_sim import __version__

rclpy.init()
node = rclpy.create_node("railderail_setup_check")
node.create_publisher(railderail_msgs.msg.WheelsetStates, "setup_check", 1)
node.destroy_node()
rclpy.shutdown()
print(f"railderail {__version__}: railderail_msgs imports and an rclpy node starts")
EOF
}

python_version() { "$1" -c 'import sys; print("%d.%d" % sys.version_info[:2])'; }

# check_python: die unless $PYTHON is Python 3.11 or 3.12; sets $version.
check_python() {
    local pick="Pick a Python 3.11 or 3.12 interpreter, e.g.  PYTHON=python3.11 ./scripts/setup.sh"
    command -v "$PYTHON" >/dev/null || die "no '$PYTHON' found. $pick"
    version=$(python_version "$PYTHON") || die "cannot run '$PYTHON'. $pick"
    case $version in
        3.11 | 3.12) ;;
        *) die "'$PYTHON' is Python $version; railderail is set up for Python 3.11 or 3.12. $pick" ;;
    esac
}

hash=$(inputs_hash)
mkdir -p "$LOGS"

if [[ -d $VENV && ! -f $STAMP ]]; then
    say "removing an incomplete .venv left by an interrupted run"
    rm -rf "$VENV"
fi
if [[ -n ${PYTHON:-} ]]; then
    check_python
    if [[ -d $VENV && $(python_version "$VPY") != "$version" ]]; then
        say "the .venv has Python $(python_version "$VPY"), PYTHON=$PYTHON is $version: making a new .venv"
        rm -rf "$VENV"
    fi
fi

if [[ -d $VENV && $(cat "$STAMP") == "$hash" ]]; then
    say ".venv is up to date (delete .venv to rebuild it from scratch)"
    run_step "checking the installation" check.log \
        "the .venv is broken: rebuild it with  rm -rf .venv build && ./scripts/setup.sh" check_venv
    exit 0
fi

for tool in cmake c++; do
    command -v $tool >/dev/null || die "'$tool' not found: it builds railderail_msgs. Install it (Debian/Ubuntu: apt-get install cmake g++) and run this again."
done

if [[ ! -d $VENV ]]; then
    PYTHON=${PYTHON:-python3}
    check_python
    # A failed or interrupted first build removes the half-made .venv (a stamp-less .venv left
    # by a killed run is removed at the next start, above).
    trap 'status=$?; if [[ $status != 0 && ! -f $STAMP ]]; then say "removing the incomplete .venv"; rm -rf "$VENV"; fi' EXIT
    trap 'exit 130' INT
    trap 'exit 143' TERM
    rm -rf "$MSG_BUILD"
    run_step "creating .venv with $PYTHON (Python $version)" venv.log \
        "check that '$PYTHON -m venv' works (Debian/Ubuntu: apt-get install python3-venv)." \
        "$PYTHON" -m venv "$VENV"
else
    say "updating .venv: requirements, constraints, messages or this script changed"
    # Until this update completes, the venv matches no inputs: a failed update is redone next time.
    echo "update started" >"$STAMP"
fi

PIP=("$VPY" -m pip --disable-pip-version-check)
pip_hint="pip could not install a pinned package: check the network and that constraints.txt (versions) and requirements.txt agree; then run this again."
run_step "installing pip and setuptools" pip-bootstrap.log "$pip_hint" \
    "${PIP[@]}" install -c constraints.txt pip setuptools
run_step "installing the pinned packages (ROS 2 wheels, numba, ...) and railderail (editable)" pip.log "$pip_hint" \
    "${PIP[@]}" install -c constraints.txt --no-build-isolation -r requirements.txt -e .

cmake_env=(env VIRTUAL_ENV="$VENV" PATH="$VENV/bin:$PATH" AMENT_PREFIX_PATH="$VENV")
msg_hint="fix the error in msg_defs/ (message files, CMakeLists.txt), then run this again."
run_step "configuring railderail_msgs (CMake)" msgs-configure.log "$msg_hint" \
    "${cmake_env[@]}" cmake -S msg_defs -B "$MSG_BUILD" -DCMAKE_BUILD_TYPE=Release -DBUILD_TESTING=OFF \
    -DCMAKE_PREFIX_PATH="$VENV" -DCMAKE_INSTALL_PREFIX="$VENV" -DPython3_EXECUTABLE="$VPY"
run_step "building railderail_msgs" msgs-build.log "$msg_hint" \
    "${cmake_env[@]}" cmake --build "$MSG_BUILD" --parallel "$(nproc)"
run_step "installing railderail_msgs into .venv" msgs-install.log "$msg_hint" \
    "${cmake_env[@]}" cmake --install "$MSG_BUILD"

run_step "checking the installation" check.log \
    "see the log; if the .venv is broken, rebuild it with  rm -rf .venv build && ./scripts/setup.sh" check_venv
echo "$hash" >"$STAMP"
say "ready: run  .venv/bin/railderail --help"
