#!/usr/bin/env bash
# A restart whose folder is read-only continues: nothing is written next to
# the restart file (the stored deck is read from memory; outputs go to the
# deck's &output dir). The folder's listing (names, sizes, times) and the
# file's checksum must be unchanged after the run. As root (chmod does not
# stop root) the folder is made a read-only bind mount, so that any write to
# it fails; otherwise it is chmod a-w.
# Usage: restart_readonly.sh EXE DECK N WORKDIR
set -u
exe=$1 deck=$2 n=$3 dir=$4
. "$(dirname "$0")/restart_lib.sh"
rm -rf "$dir"; mkdir -p "$dir"; cd "$dir" || exit 1
dump=$(printf 'out/ro_restart_%08d.h5' "$n")
derive part1 "$deck" "max_steps = $n, dump_steps = $n" ro
"$exe" part1.nml > part1.log 2>&1 || fail "first part failed"
mkdir ro && cp "$dump" ro/r.h5 || fail "no dump $dump"
how="chmod a-w"
if [ "$(id -u)" -eq 0 ] && mount --bind ro ro 2> /dev/null; then
  trap 'umount "$PWD/ro" 2> /dev/null' EXIT
  if mount -o remount,bind,ro ro 2> /dev/null; then
    how="a read-only bind mount"
  else
    umount ro; trap - EXIT
  fi
fi
[ "$how" = "chmod a-w" ] && chmod a-w ro
if touch ro/probe 2> /dev/null; then
  rm -f ro/probe
  echo "note: the folder is writable for this user (root without mounts): only its listing is checked"
fi
before=$(ls -la --full-time ro | grep -v " \.\.$"; md5sum ro/r.h5)
derive cont "$deck" "max_steps = $((2*n)), restart_from = 'ro/r.h5'" cont
"$exe" cont.nml > cont.log 2>&1 || { tail -5 cont.log; fail "the restart from a read-only folder failed"; }
grep -q "restarted from ro/r.h5 at step $n" cont.log || fail "restart not reported"
grep -q "done: .* after $((2*n)) steps" cont.log || fail "did not run to step $((2*n))"
after=$(ls -la --full-time ro | grep -v " \.\.$"; md5sum ro/r.h5)
[ "$before" = "$after" ] || { diff <(echo "$before") <(echo "$after"); fail "the restart folder changed"; }
[ "$how" = "chmod a-w" ] && chmod u+w ro
echo "ok: continued from a folder made read-only by $how; its listing is unchanged"
echo "PASS restart_readonly"
