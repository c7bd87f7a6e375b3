#!/bin/bash
# docs/cluster.md's Slurm scripts, run for real.
#
# Starts a private one-node Slurm on this machine (munged, slurmctld, slurmd, all three in the
# foreground of this script, with their key, sockets, state and logs under WORK), submits the job
# array and the merge job extracted from docs/cluster.md (fenced blocks after a `<!-- slurm-test:
# NAME -->` marker) with only the array size, N, --cpus-per-task and --cases changed, waits for
# them with a bounded timeout, and compares the merge's table and case count with an unsharded run
# of the same campaign. Stops exactly the daemons it started (their own pids) on every exit.
# An existing munged is not disturbed: ours has its own key and socket (slurm.conf's AuthInfo).
# An existing Slurm makes the test skip: it is never used nor stopped.
#
# usage: run_slurm_test.sh RAYPROOF_BIN CLUSTER_MD WORK
# Exit status: 0 passed, 1 failed, 77 skipped (CTest's SKIP_RETURN_CODE): not root, slurm-wlm or
# munge missing, a Slurm already running here (this test never touches another Slurm), or a daemon
# that does not start. RAYPROOF_SLURM_REQUIRED=1 turns a skip into a failure (for a CI that has
# the packages and must run it). RAYPROOF_SLURM_TIMEOUT (seconds, default 120) bounds the wait.
set -u
RAYPROOF=${1:?usage: run_slurm_test.sh RAYPROOF_BIN CLUSTER_MD WORK}
DOC=${2:?cluster.md}
WORK=${3:?scratch directory}
SHARDS=3          # --array=1-3 and N=3
CPUS=1            # --cpus-per-task
CASES=${RAYPROOF_SLURM_CASES:-12288}
TIMEOUT=${RAYPROOF_SLURM_TIMEOUT:-120}
PATH=$PATH:/usr/sbin:/sbin
START=$SECONDS

log() { echo "slurm_test: $*"; }
skip() {
  if [ "${RAYPROOF_SLURM_REQUIRED:-0}" = 1 ]; then log "FAIL (RAYPROOF_SLURM_REQUIRED=1): would skip: $*"; exit 1; fi
  log "SKIP: $*"; exit 77
}
fail() { log "FAIL: $*"; exit 1; }

# --- Can this machine run it? -------------------------------------------------------------------
[ "$(id -u)" = 0 ] || skip "needs root to start slurmd, slurmctld and munged (uid $(id -u))"
for b in munged mungekey munge unmunge slurmctld slurmd sbatch squeue scontrol sinfo scancel; do
  command -v "$b" >/dev/null || skip "$b not found: apt-get install --no-install-recommends slurm-wlm munge"
done
[ -x "$RAYPROOF" ] || fail "no rayproof binary at $RAYPROOF"
[ -f "$DOC" ] || fail "no $DOC"
RAYPROOF=$(realpath "$RAYPROOF") DOC=$(realpath "$DOC") WORK=$(realpath -m "$WORK")

# Processes by name, from /proc (procps may be missing): pids_named [-z] NAME... prints the pids of
# the live processes of those names (with -z, of the zombies too).
pids_named() {
  local d comm st zombies=0 n
  [ "$1" = -z ] && { zombies=1; shift; }
  for d in /proc/[0-9]*; do
    { read -r comm <"$d/comm"; read -r _ _ st _ <"$d/stat"; } 2>/dev/null || continue
    [ "$st" = Z ] && [ $zombies = 0 ] && continue
    for n in "$@"; do [ "$comm" = "$n" ] && echo "${d#/proc/}"; done
  done
}

# One run of this test at a time on the machine (two build trees may run it at once); then no
# other Slurm may be running: this test never submits to, nor stops, a Slurm it did not start.
exec 9>/tmp/rayproof_slurm_test.lock
flock -w 300 9 || skip "another run of this test held /tmp/rayproof_slurm_test.lock for 300 s"
pids=$(pids_named slurmctld slurmd slurmstepd slurmdbd)
[ -z "$pids" ] || skip "a Slurm is already running here (pids $(echo $pids)): this test leaves it alone"

# --- Scratch directory and cleanup --------------------------------------------------------------
rm -rf "$WORK"
mkdir -p "$WORK"/{munge,state,spool,jobs,bin,whole} || fail "cannot create $WORK"
chmod 755 "$WORK" "$WORK/munge"   # munged wants its socket's directory searchable, not writable, by all
MUNGED_PID= CTLD_PID= SLURMD_PID= WHOLE_PID=
export SLURM_CONF=$WORK/slurm.conf

stop_pid() {  # stop_pid NAME PID: TERM, wait up to 10 s, then KILL
  local name=$1 pid=$2 i
  [ -n "$pid" ] && kill -0 "$pid" 2>/dev/null || return 0
  kill -TERM "$pid" 2>/dev/null
  for i in $(seq 100); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
  if kill -0 "$pid" 2>/dev/null; then log "$name (pid $pid) ignored TERM: KILL"; kill -KILL "$pid" 2>/dev/null; fi
  wait "$pid" 2>/dev/null
  log "stopped $name (pid $pid)"
}
# The job steps of our slurmd (live ones: not zombies): they carry our SLURM_CONF in their environment.
our_stepds() {
  local p
  for p in $(pids_named slurmstepd); do
    { tr '\0' '\n' <"/proc/$p/environ"; } 2>/dev/null | grep -qx "SLURM_CONF=$SLURM_CONF" && echo "$p"
  done
}
cleanup() {
  local rc=$? i p
  trap - EXIT INT TERM HUP
  [ -n "$WHOLE_PID" ] && stop_pid "the unsharded run" "$WHOLE_PID"
  if [ -n "$CTLD_PID" ] && kill -0 "$CTLD_PID" 2>/dev/null; then
    if [ -n "$(squeue -h -o %i 2>/dev/null)" ]; then  # a failure or a timeout: cancel what is left
      log "cancelling jobs $(squeue -h -o %A 2>/dev/null | sort -u | tr '\n' ' ')"
      scancel --full --quiet $(squeue -h -o %A 2>/dev/null | sort -u) 2>/dev/null
      for i in $(seq 100); do [ -z "$(squeue -h -o %i 2>/dev/null)" ] && break; sleep 0.2; done
    fi
  fi
  for i in $(seq 100); do [ -z "$(our_stepds)" ] && break; sleep 0.1; done
  stop_pid slurmd "$SLURMD_PID"
  stop_pid slurmctld "$CTLD_PID"
  stop_pid munged "$MUNGED_PID"
  for p in $(our_stepds); do log "killing leftover slurmstepd $p"; kill -KILL "$p" 2>/dev/null; done
  # Exited steps are reaped by init a moment later: wait for that (no other Slurm ran when we began).
  for i in $(seq 50); do [ -z "$(pids_named -z slurmstepd)" ] && break; sleep 0.1; done
  if [ "$rc" = 0 ] && [ "${RAYPROOF_SLURM_KEEP:-0}" != 1 ]; then rm -rf "$WORK"; fi
  log "done in $((SECONDS - START)) s (exit $rc)"
  exit "$rc"
}
trap cleanup EXIT
trap 'log "interrupted"; exit 1' INT TERM HUP

tail_logs() { for f in "$@"; do [ -f "$f" ] && { echo "--- $f"; tail -n 20 "$f"; }; done; }

# --- The scripts from docs/cluster.md -----------------------------------------------------------
# extract NAME: the fenced block after the line `<!-- slurm-test: NAME -->`.
extract() {
  awk -v name="$1" '
    $0 == "<!-- slurm-test: " name " -->" { armed = 1; next }
    armed && /^```/ { if (inside) exit; inside = 1; next }
    inside { print }' "$DOC"
}
cd "$WORK/jobs" || fail "cd $WORK/jobs"
for name in fuzz-shard.sbatch fuzz-merge.sbatch submit.sh; do
  extract "$name" >"$WORK/doc-$name"
  [ -s "$WORK/doc-$name" ] || fail "$DOC has no fenced block after <!-- slurm-test: $name -->"
done
# The four changes, each of which must match exactly one line of the shard script.
pats=('^#SBATCH --array=1-[0-9][0-9]*$' '^N=[0-9][0-9]*' '^#SBATCH --cpus-per-task=[0-9][0-9]*$' '--cases [0-9][0-9]*')
reps=("#SBATCH --array=1-$SHARDS" "N=$SHARDS" "#SBATCH --cpus-per-task=$CPUS" "--cases $CASES")
cp "$WORK/doc-fuzz-shard.sbatch" fuzz-shard.sbatch
for i in "${!pats[@]}"; do
  n=$(grep -c -- "${pats[i]}" "$WORK/doc-fuzz-shard.sbatch")
  [ "$n" = 1 ] || fail "docs/cluster.md's fuzz-shard.sbatch: '${pats[i]}' matches $n lines, not 1"
  sed -i -e "s/${pats[i]}/${reps[i]}/" fuzz-shard.sbatch
done
cp "$WORK/doc-fuzz-merge.sbatch" fuzz-merge.sbatch
cp "$WORK/doc-submit.sh" submit.sh
log "the scripts of $DOC, changed only as follows:"
diff -U0 --label docs/fuzz-shard.sbatch --label fuzz-shard.sbatch "$WORK/doc-fuzz-shard.sbatch" fuzz-shard.sbatch | grep '^[-+][^-+]'
[ "$(diff "$WORK/doc-fuzz-shard.sbatch" fuzz-shard.sbatch | grep -c '^>')" = 4 ] || fail "expected 4 changed lines"
grep -q -- 'sbatch --parsable' submit.sh && grep -q -- '--dependency=afterok' submit.sh ||
  fail "the submission block no longer uses sbatch --parsable and --dependency=afterok"

# The unsharded run: the shard script's rayproof fuzz command without --shard, --jobs, --out, --summary.
cmdline=$(sed -e ':a' -e '/\\$/N; s/\\\n//; ta' fuzz-shard.sbatch | grep -m1 '^rayproof fuzz ')
[ -n "$cmdline" ] || fail "no 'rayproof fuzz' command in fuzz-shard.sbatch"
read -ra words <<<"${cmdline#rayproof fuzz }"
whole_args=()
for ((i = 0; i < ${#words[@]}; ++i)); do
  case ${words[i]} in
    --shard | --jobs | --out | --summary) ((++i)) ;;
    *'$'* | *'"'* | *"'"* | *'`'*) fail "cannot derive the unsharded run from fuzz-shard.sbatch: '${words[i]}'" ;;
    *) whole_args+=("${words[i]}") ;;
  esac
done
log "unsharded run: rayproof fuzz ${whole_args[*]} --jobs 2"

# --- munged, slurmctld, slurmd: private instances -----------------------------------------------
mungekey -c -k "$WORK/munge/munge.key" >/dev/null 2>&1 || skip "mungekey cannot create a key"
munged -F --socket="$WORK/munge/munge.sock" --key-file="$WORK/munge/munge.key" \
  --pid-file="$WORK/munge/munged.pid" --log-file="$WORK/munge/munged.log" --seed-file="$WORK/munge/munged.seed" \
  >"$WORK/munge/munged.out" 2>&1 9>&- &
MUNGED_PID=$!
for i in $(seq 50); do [ -S "$WORK/munge/munge.sock" ] && break; kill -0 $MUNGED_PID 2>/dev/null || break; sleep 0.1; done
munge -n -S "$WORK/munge/munge.sock" 2>/dev/null | unmunge -S "$WORK/munge/munge.sock" >/dev/null 2>&1 || {
  tail_logs "$WORK/munge/munged.out" "$WORK/munge/munged.log"; skip "munged does not start or munge -n | unmunge fails"; }
log "munged (pid $MUNGED_PID) on $WORK/munge/munge.sock"

free_port() {  # a TCP port nobody listens on (state 0A in /proc/net/tcp*), from $1 up
  local p listening
  listening=$(cat /proc/net/tcp /proc/net/tcp6 2>/dev/null | awk '$4 == "0A" { split($2, a, ":"); print a[2] }')
  for ((p = $1; p < 30000; ++p)); do
    echo "$listening" | grep -qx "$(printf %04X $p)" || { echo $p; return; }
  done
  return 1
}
CTLD_PORT=$(free_port 26817) && SLURMD_PORT=$(free_port $((CTLD_PORT + 1))) || skip "no free TCP port"
H=${HOSTNAME%%.*}   # the short host name, as slurmd finds it
cat >"$SLURM_CONF" <<EOF
ClusterName=rayproof-test
SlurmctldHost=$H
SlurmctldPort=$CTLD_PORT
SlurmdPort=$SLURMD_PORT
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$WORK/munge/munge.sock
StateSaveLocation=$WORK/state
SlurmdSpoolDir=$WORK/spool
SlurmctldPidFile=$WORK/slurmctld.pid
SlurmdPidFile=$WORK/slurmd.pid
SlurmctldLogFile=$WORK/slurmctld.log
SlurmdLogFile=$WORK/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
MpiDefault=none
JobAcctGatherType=jobacct_gather/none
MailProg=/bin/true
NodeName=$H CPUs=$(nproc) RealMemory=1000 State=UNKNOWN
PartitionName=main Nodes=$H Default=YES MaxTime=INFINITE State=UP
EOF
log "slurm.conf: $SLURM_CONF (ports $CTLD_PORT, $SLURMD_PORT)"
slurmctld -D -f "$SLURM_CONF" >"$WORK/slurmctld.out" 2>&1 9>&- &
CTLD_PID=$!
slurmd -D -f "$SLURM_CONF" >"$WORK/slurmd.out" 2>&1 9>&- &
SLURMD_PID=$!
state=
for i in $(seq 150); do
  state=$(sinfo -h -N -o %T 2>/dev/null)
  [ "$state" = idle ] && break
  kill -0 $CTLD_PID 2>/dev/null && kill -0 $SLURMD_PID 2>/dev/null || break
  sleep 0.2
done
if [ "$state" != idle ]; then
  tail_logs "$WORK/slurmctld.out" "$WORK/slurmctld.log" "$WORK/slurmd.out" "$WORK/slurmd.log"
  skip "slurmctld (pid $CTLD_PID) and slurmd (pid $SLURMD_PID) did not bring node $H up (state '${state}')"
fi
log "slurmctld (pid $CTLD_PID), slurmd (pid $SLURMD_PID): node $H idle after $((SECONDS - START)) s"

# --- Submit as the docs say, run the unsharded campaign meanwhile -------------------------------
mkdir -p "$WORK/bin" && ln -sf "$RAYPROOF" "$WORK/bin/rayproof"
export PATH=$WORK/bin:$PATH   # the jobs inherit it (sbatch exports the environment)
submitted=$(bash -e -c 'source ./submit.sh; echo "ARRAY=$ARRAY"' 2>&1) || fail "submission failed: $submitted"
echo "$submitted" | sed 's/^/  /'
ARRAY=$(echo "$submitted" | sed -n 's/^ARRAY=\([0-9][0-9]*\)$/\1/p')
MERGE=$(echo "$submitted" | sed -n 's/^Submitted batch job \([0-9][0-9]*\)$/\1/p')
[ -n "$ARRAY" ] && [ -n "$MERGE" ] || fail "no job ids in the submission's output"
log "array job $ARRAY, merge job $MERGE (afterok:$ARRAY)"

rayproof fuzz "${whole_args[@]}" --jobs 2 --out "$WORK/whole/findings" --summary "$WORK/whole/whole.json" \
  >"$WORK/whole/out.txt" 2>"$WORK/whole/err.txt" &
WHOLE_PID=$!

task_states() { scontrol -o show job "$ARRAY" | grep -o ' ArrayTaskId=[^ ]*\| JobState=[^ ]*\| ExitCode=[^ ]*' | paste -d '' - - -; }
job_field() { scontrol -o show job "$1" 2>/dev/null | grep -o "$2=[^ ]*" | sed "s/^$2=//"; }
deadline=$((SECONDS + TIMEOUT))
while :; do
  mstate=$(job_field "$MERGE" JobState)
  case $mstate in COMPLETED | FAILED | CANCELLED | TIMEOUT | NODE_FAIL | OUT_OF_MEMORY | BOOT_FAIL | DEADLINE) break ;; esac
  if [ "$(job_field "$MERGE" Reason)" = DependencyNeverSatisfied ]; then
    task_states
    tail_logs rayproof-fuzz-*.log
    fail "a shard failed: the merge job's afterok dependency can never be satisfied"
  fi
  if ((SECONDS >= deadline)); then
    squeue; tail_logs rayproof-*.log "$WORK/slurmctld.log" "$WORK/slurmd.log"
    fail "timeout: the jobs had not finished after $TIMEOUT s (merge job $MERGE: '$mstate')"
  fi
  sleep 0.5
done
log "merge job $MERGE: $mstate after $((SECONDS - START)) s"
wait $WHOLE_PID
whole_rc=$?

# --- Check ---------------------------------------------------------------------------------------
ok=1
tasks=$(task_states)
echo "$tasks" | sed 's/^/  /'
[ "$(echo "$tasks" | grep -c ' JobState=COMPLETED ExitCode=0:0$')" = $SHARDS ] || { ok=0; log "not $SHARDS completed shards"; }
[ "$mstate" = COMPLETED ] && [ "$(job_field "$MERGE" ExitCode)" = 0:0 ] || { ok=0; log "merge job: $mstate, exit $(job_field "$MERGE" ExitCode)"; }
[ "$whole_rc" = 0 ] || { ok=0; log "the unsharded run exited with $whole_rc"; tail_logs "$WORK/whole/err.txt"; }
mlog=$(ls rayproof-merge-"$MERGE".log 2>/dev/null)
[ -n "$mlog" ] || fail "no rayproof-merge-$MERGE.log"
[ -f campaign/merged.json ] || { ok=0; log "no campaign/merged.json"; }
((ok)) || { tail_logs rayproof-*.log; fail "the jobs did not all succeed"; }

# The table: the printed lines up to the first blank line, in the merge job's log and in the unsharded run's output.
table() { awk 'NF == 0 { exit } { print }' "$1"; }
table "$mlog" >merged-table.txt
table "$WORK/whole/out.txt" >whole-table.txt
log "the merge job's table ($mlog), $(wc -l <merged-table.txt) lines, its (all) rows:"
{ head -n 1 merged-table.txt; grep -F '(all)' merged-table.txt; } | sed 's/^/  /'
[ "$(wc -l <whole-table.txt)" -ge 2 ] || fail "the unsharded run printed no table: $(head -c 300 "$WORK/whole/out.txt")"
diff -u whole-table.txt merged-table.txt >table.diff || { cat table.diff; fail "the merge's table differs from the unsharded run's"; }
grep -q "from $SHARDS shards" "$mlog" || fail "the merge job's log does not say 'from $SHARDS shards'"
# The line after the table: "R rounds, C cases in ..." (unsharded) and "R rounds, C cases from N shards" (merged).
counts() { grep -m1 -o '^[0-9][0-9]* rounds, [0-9][0-9]* cases' "$1"; }
wcount=$(counts "$WORK/whole/out.txt") && mcount=$(counts "$mlog") || fail "no 'R rounds, C cases' line in the outputs"
[ "$wcount" = "$mcount" ] || fail "unsharded: $wcount; merged: $mcount"
[ "${wcount#* rounds, }" != "0 cases" ] || fail "the campaign has no cases"
[ -s campaign/merged.json ] || fail "the merge job wrote no campaign/merged.json"
log "unsharded: $wcount; merged: $mcount"
log "PASS: the merge of $SHARDS Slurm shards equals the unsharded run ($((SECONDS - START)) s)"
exit 0
