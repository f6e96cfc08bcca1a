#!/usr/bin/env bash
# Runs the example sweep as a 3-task Slurm job array on a throwaway single-node
# Slurm (munged + slurmctld + slurmd on localhost), merges the parts, and checks
# that the merged records.csv equals an unsharded run's (runtime_ms aside).
#
# Needs root (it may apt-get install slurm-wlm). Prints `SKIP: ...` and exits 0
# where Slurm can't be installed or started; exits 1 if the records differ.
# Env: MRPP (default target/release/mrpp), CONFIG (default
# bench/configs/example.toml), SLURM_TEST_PORT (slurmctld port, default 16817;
# slurmd uses +1), KEEP_TMP=1 keeps the temp dir.
set -euo pipefail

REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
cd "$REPO"

skip() { echo "SKIP: $*"; exit 0; }
abspath() { case $1 in /*) echo "$1" ;; *) echo "$REPO/$1" ;; esac; }

MRPP=$(abspath "${MRPP:-target/release/mrpp}")
CONFIG=$(abspath "${CONFIG:-bench/configs/example.toml}")
PORT=${SLURM_TEST_PORT:-16817}

# Build the CLI once if the default binary is missing.
if [[ ! -x $MRPP && $MRPP == "$REPO/target/release/mrpp" ]]; then
    cargo build --release -p mrpp-cli
fi
[[ -x $MRPP ]] || { echo "error: $MRPP is not executable" >&2; exit 1; }

TMP=$(mktemp -d /tmp/slurm-local-test.XXXXXX)
chmod 755 "$TMP"
PIDS=()
export SLURM_CONF=$TMP/etc/slurm.conf  # read by sbatch, sinfo, scancel
JOBID=
cleanup() {
    local rc=$?
    set +e
    [[ -n $JOBID ]] && scancel "$JOBID" 2>/dev/null && sleep 1
    # Stop only the daemons started here, newest first.
    for ((i = ${#PIDS[@]} - 1; i >= 0; i--)); do kill "${PIDS[i]}" 2>/dev/null; done
    for pid in "${PIDS[@]}"; do
        for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
        kill -9 "$pid" 2>/dev/null
    done
    if [[ ${KEEP_TMP:-0} == 1 ]]; then echo "kept $TMP"; else rm -rf "$TMP"; fi
    exit "$rc"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

# 1. Install Slurm (and munge, a dependency of it) if needed.
if ! command -v sbatch >/dev/null || ! command -v slurmctld >/dev/null \
    || ! command -v slurmd >/dev/null || ! command -v munged >/dev/null; then
    [[ $(id -u) == 0 ]] || skip "slurm-wlm cannot be installed here (not root)"
    command -v apt-get >/dev/null || skip "slurm-wlm cannot be installed here (no apt-get)"
    export DEBIAN_FRONTEND=noninteractive
    apt_install() { apt-get install -y --no-install-recommends slurm-wlm munge >"$TMP/apt.log" 2>&1; }
    if ! apt_install; then
        # A fresh machine may have no package lists yet.
        apt-get update >>"$TMP/apt.log" 2>&1 || true
        apt_install || skip "slurm-wlm cannot be installed here ($(grep -E '^E:' "$TMP/apt.log" | tail -1 || tail -1 "$TMP/apt.log"))"
    fi
fi
logtail() {
    for f in "$TMP"/log/*; do echo "--- ${f##*/}"; tail -n 20 "$f"; done
}

# 2. A private munged (own key and socket) and a one-node slurm.conf.
mkdir -p "$TMP"/{etc,log,munge,state,spool,parts,jobs}
chmod 711 "$TMP/munge"  # munged wants its socket dir searchable by all
dd if=/dev/urandom of="$TMP/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$TMP/munge/munge.key"
SOCK=$TMP/munge/munge.socket
munged --foreground --force --key-file="$TMP/munge/munge.key" --socket="$SOCK" \
    --pid-file="$TMP/munge/munged.pid" --seed-file="$TMP/munge/munged.seed" \
    >>"$TMP/log/munged.log" 2>&1 &
PIDS+=($!)

HOST=$(hostname -s)
cat >"$SLURM_CONF" <<EOF
ClusterName=mrpplocal
SlurmctldHost=$HOST(127.0.0.1)
SlurmctldPort=$PORT
SlurmdPort=$((PORT + 1))
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$SOCK
StateSaveLocation=$TMP/state
SlurmdSpoolDir=$TMP/spool
SlurmctldPidFile=$TMP/slurmctld.pid
SlurmdPidFile=$TMP/slurmd.pid
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SwitchType=switch/none
MpiDefault=none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/none
MailProg=/bin/true
ReturnToService=2
NodeName=$HOST NodeAddr=127.0.0.1 CPUs=$(nproc) RealMemory=100 State=UNKNOWN
PartitionName=local Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF

echo "$(sbatch --version), $(munged --version 2>&1 | awk '{print $1; exit}')"
for _ in $(seq 50); do [[ -S $SOCK ]] && break; sleep 0.1; done
[[ -S $SOCK ]] || skip "munged did not start: $(logtail)"

slurmctld -D -c -f "$SLURM_CONF" >>"$TMP/log/slurmctld.log" 2>&1 &  # -D: log to stderr
PIDS+=($!)
slurmd -D -f "$SLURM_CONF" -N "$HOST" >>"$TMP/log/slurmd.log" 2>&1 &
PIDS+=($!)

# Wait (60 s at most) for the node to be idle.
state=
for _ in $(seq 60); do
    state=$(sinfo -h -N -n "$HOST" -o %T 2>/dev/null || true)
    [[ $state == idle ]] && break
    sleep 1
done
[[ $state == idle ]] || skip "slurm node not idle after 60 s (state: '${state:-none}')
$(logtail)"
echo "node $HOST idle after $SECONDS s"

# 3. The job array: one shard per task.
MERGED=$TMP/merged WHOLE=$TMP/whole PARTS=$TMP/parts
cat >"$TMP/jobs/shard.sh" <<'EOF'
#!/usr/bin/env bash
set -euo pipefail
echo "task $SLURM_ARRAY_TASK_ID of job $SLURM_ARRAY_JOB_ID on $(hostname -s)"
exec "$MRPP" bench run --config "$CONFIG" --shard "${SLURM_ARRAY_TASK_ID}/3" --out "$PARTS"
EOF
start=$SECONDS
# --wait blocks until all 3 tasks end and fails if any failed; --parsable
# prints the job id first so the EXIT trap can scancel a job left behind.
if ! MRPP=$MRPP CONFIG=$CONFIG PARTS=$PARTS timeout 900 sbatch --wait --parsable \
    --array=1-3 --export=ALL,MRPP,CONFIG,PARTS --ntasks=1 --chdir="$REPO" \
    --output="$TMP/log/shard-%a.out" --job-name=mrpp-shards "$TMP/jobs/shard.sh" >"$TMP/jobid"; then
    JOBID=$(cut -d';' -f1 "$TMP/jobid")
    echo "error: array job ${JOBID:-?} failed" >&2; logtail >&2; exit 1
fi
for i in 1 2 3; do
    if [[ ! -s $PARTS/part-$i-of-3.jsonl ]]; then
        echo "error: shard $i wrote no part" >&2; logtail >&2; exit 1
    fi
done
echo "array job $(cut -d';' -f1 "$TMP/jobid") done in $((SECONDS - start)) s: $(grep -h '^task' "$TMP"/log/shard-*.out | tr '\n' ';')"

"$MRPP" bench merge --out "$MERGED" "$PARTS" >/dev/null
"$MRPP" bench run --config "$CONFIG" --out "$WHOLE" >"$TMP/log/whole.out" 2>&1

bash "$REPO/tools/cluster/same-records.sh" "$WHOLE/records.csv" "$MERGED/records.csv" "slurm array of 3 shards"
