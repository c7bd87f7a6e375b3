#!/bin/bash
# Times the README's first command on a bare Debian 12 root made here: debootstrap
# bookworm (Debian's required and important packages, as a fresh install has), this checkout copied
# in as a fresh clone, then the command exactly as the README has it, run as root in a chroot, with
# a timestamp at each phase (apt, configure, build, report). Needs root, debootstrap and Debian's
# mirror; it writes only under WORK. Not a test (network, minutes): docs/commands.md#first-run has
# what it measured.
#
#   bench/first_run/bare_debian.sh [WORK]    (default /tmp/rayproof-bare)
set -euo pipefail
src=$(cd "$(dirname "$0")/../.." && pwd)
work=${1:-/tmp/rayproof-bare}
root=$work/root
[ "$(id -u)" = 0 ] || { echo "bare_debian.sh: run as root (debootstrap, chroot)" >&2; exit 2; }
command -v debootstrap >/dev/null || { echo "bare_debian.sh: needs debootstrap (apt-get install -y debootstrap)" >&2; exit 2; }
cleanup() { umount "$root/proc" "$root/dev" 2>/dev/null || true; }
trap cleanup EXIT
if [ ! -d "$work/pristine" ]; then
  mkdir -p "$work"
  debootstrap bookworm "$work/pristine" http://deb.debian.org/debian
  printf 'deb http://deb.debian.org/debian bookworm main\ndeb http://deb.debian.org/debian bookworm-updates main\ndeb http://deb.debian.org/debian-security bookworm-security main\n' \
    > "$work/pristine/etc/apt/sources.list"
fi
rm -rf "$root" && cp -a "$work/pristine" "$root"
cp /etc/resolv.conf "$root/etc/resolv.conf"
git clone -q "$src" "$root/root/rayproof"
# The README's first command, cut at its phases: apt; cmake configure; the build; the report.
line=$(grep -m1 '^P="g++ cmake make ninja-build pkgconf' "$src/README.md")
apt=${line%%; cmake -S*}
rest="cmake -S${line#*; cmake -S}"   # from the configure on
configure=${rest%% && cmake --build*}
build=${rest#* && }; build=${build%% && build/rayproof*}
report=${rest##* && }
[ "$apt; $configure && $build && $report" = "$line" ] || { echo "bare_debian.sh: the README's first command changed shape" >&2; exit 2; }
mount -t proc proc "$root/proc"
mount --bind /dev "$root/dev"
cat > "$root/root/phases.sh" <<PHASES
cd /root/rayproof
t() { date +%s.%N; }
t0=\$(t); $apt; t1=\$(t); $configure; t2=\$(t); $build; t3=\$(t); $report; t4=\$(t)
awk -v a=\$t0 -v b=\$t1 -v c=\$t2 -v d=\$t3 -v e=\$t4 'BEGIN { printf "apt %.1f s, configure %.1f s, build %.1f s, report %.1f s, whole command %.1f s\n", b-a, c-b, d-c, e-d, e-a }'
PHASES
chroot "$root" /usr/bin/env -i PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin HOME=/root \
  DEBIAN_FRONTEND=noninteractive bash -e /root/phases.sh > "$work/first_run.log" 2>&1
tail -1 "$work/first_run.log"
grep -E '^(Fetched|[0-9]+ upgraded)' "$work/first_run.log" || true
