#!/usr/bin/env bash
# End-to-end checks of the kizamu executable: generate, info, damaged files, and the
# benchmark's JSON contract. Usage: cli_test.sh path/to/kizamu [mimalloc|default] [bench|nobench]
# [render|norender] (the third argument: whether the build has the benchmarks, KIZAMU_BUILD_BENCH;
# the fourth: whether it has the renderer, KIZAMU_BUILD_RENDER)
set -uo pipefail
kizamu="$1"
allocator="${2:-default}"
benchmarks="${3:-bench}"
renderer="${4:-render}"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
finish() {
    if [ "$failures" -eq 0 ]; then echo "cli: all checks passed"; exit 0; fi
    echo "cli: $failures check(s) failed"; exit 1
}

# --version names the allocator actually serving malloc (asked of the allocator, not the build)
version=$("$kizamu" --version) || fail "--version exited non-zero"
grep -q "^kizamu [0-9]" <<<"$version" || fail "--version lacks the version: $version"
if [ "$allocator" = mimalloc ]; then
    grep -q "^memory: mimalloc [0-9.]* serves malloc, huge pages advised, freed memory kept; this thread's heap: " <<<"$version" ||
        fail "built with mimalloc, but: $version"
    # Where the kernel gives huge pages on request (and says so), the command's heap may have
    # them (main.cpp runs commands on a thread started after the policy: the main thread's
    # heap began in 4 KiB pages).
    if grep -q "\\[madvise\\]" /sys/kernel/mm/transparent_hugepage/enabled 2>/dev/null &&
        ! grep -q "this thread's heap: unknown$" <<<"$version"; then
        grep -q "this thread's heap: huge pages allowed$" <<<"$version" ||
            fail "the command's heap is not huge-page backed: $version"
    fi
else
    grep -q "^memory: " <<<"$version" && ! grep -q "mimalloc" <<<"$version" || fail "built without mimalloc, but: $version"
fi

# generate + info
"$kizamu" generate --level 7 --out "$tmp/p.kza" >/dev/null || fail "generate exited non-zero"
info=$("$kizamu" info "$tmp/p.kza") || fail "info exited non-zero"
for field in "level       7" "tiles" "cells" "memory" "bounds"; do
    grep -q "$field" <<<"$info" || fail "info lacks '$field'"
done
breakdown=$("$kizamu" info --breakdown "$tmp/p.kza") || fail "info --breakdown exited non-zero"
for field in "brick values" "lone-leaves" "cells by min|corner|"; do
    grep -qF "$field" <<<"$breakdown" || fail "info --breakdown lacks '$field'"
done

# damaged files: exit code 2, one line on stderr naming the file, nothing on stdout
check_bad() {
    local file="$1" expect="$2"
    out=$("$kizamu" info "$file" 2>"$tmp/err"); rc=$?
    [ "$rc" -eq 2 ] || fail "info on $(basename "$file") exited $rc, expected 2"
    [ -z "$out" ] || fail "info on $(basename "$file") printed to stdout"
    [ "$(wc -l <"$tmp/err")" -eq 1 ] || fail "error for $(basename "$file") is not one line"
    grep -q "$expect" "$tmp/err" || fail "error for $(basename "$file") lacks '$expect': $(cat "$tmp/err")"
}
size=$(stat -c %s "$tmp/p.kza")
head -c $((size / 2)) "$tmp/p.kza" >"$tmp/half.kza"
check_bad "$tmp/half.kza" "truncated"
echo "solid nothing" >"$tmp/foreign.kza"
check_bad "$tmp/foreign.kza" "not a Kizamu ADF file"
cp "$tmp/p.kza" "$tmp/flip.kza"
printf '\xff' | dd of="$tmp/flip.kza" bs=1 seek=$((size / 3)) conv=notrunc 2>/dev/null
check_bad "$tmp/flip.kza" "checksum mismatch"
check_bad "$tmp/missing.kza" "cannot open"

# convert: mesh formats, a mesh to an ADF and back, LOD, a watertight remesh; bad pairs: one line
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n' >"$tmp/tet.obj"
"$kizamu" convert "$tmp/tet.obj" "$tmp/tet.ply" >/dev/null || fail "convert obj -> ply"
"$kizamu" convert "$tmp/tet.ply" "$tmp/tet.stl" >/dev/null || fail "convert ply -> stl"
"$kizamu" convert "$tmp/tet.stl" "$tmp/tet.kza" --level 6 >/dev/null || fail "convert stl -> kza"
"$kizamu" info "$tmp/tet.kza" | grep -q "level       6" || fail "info on a converted mesh"
"$kizamu" convert "$tmp/p.kza" "$tmp/p.glb" >/dev/null || fail "convert kza -> glb"
"$kizamu" convert "$tmp/p.kza" "$tmp/p.stl" >/dev/null || fail "convert kza -> stl"
admesh "$tmp/p.stl" | grep -q "Backwards edges *: *0" || fail "kza -> stl: admesh finds backwards edges"
admesh "$tmp/p.stl" | grep -q "Edges fixed *: *0" || fail "kza -> stl: admesh had to fix edges (open mesh)"
full=$(assimp info "$tmp/p.glb" --raw | sed -n 's/^Faces: *\([0-9]*\).*/\1/p')
"$kizamu" convert "$tmp/p.kza" "$tmp/lod.ply" --lod 4 >/dev/null || fail "convert kza -> ply --lod"
lod=$(assimp info "$tmp/lod.ply" --raw | sed -n 's/^Faces: *\([0-9]*\).*/\1/p')
[ -n "$full" ] && [ -n "$lod" ] && [ "$lod" -gt 0 ] && [ "$lod" -lt "$full" ] || fail "LOD mesh ($lod faces) not smaller than full ($full)"
# --decimate: a copy beside the output, NAME.decimated.EXT, with about that fraction of the triangles
"$kizamu" convert "$tmp/p.kza" "$tmp/dec.ply" --decimate 0.5 >"$tmp/out" || fail "convert --decimate"
[ -s "$tmp/dec.decimated.ply" ] || fail "convert --decimate wrote no dec.decimated.ply"
read -r kept total < <(sed -n 's/^wrote .*dec.decimated.ply: \([0-9]*\) of \([0-9]*\) triangles.*/\1 \2/p' "$tmp/out")
[ -n "${total:-}" ] && [ $((kept * 100 / total)) -ge 40 ] && [ $((kept * 100 / total)) -le 60 ] ||
    fail "convert --decimate 0.5 kept ${kept:-?} of ${total:-?} triangles: $(cat "$tmp/out")"
"$kizamu" convert "$tmp/tet.obj" "$tmp/remesh.stl" --level 6 >/dev/null || fail "remesh obj -> stl --level"
admesh "$tmp/remesh.stl" | grep -q "Edges fixed *: *0" || fail "remesh is not closed"
# an inward-facing closed mesh: the same solid as its outward twin (closed parts oriented by nesting), with a warning
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 4 2\nf 1 3 4\nf 2 4 3\n' >"$tmp/tet_in.obj"
"$kizamu" convert "$tmp/tet_in.obj" "$tmp/remesh_in.stl" --level 6 >/dev/null 2>"$tmp/err" || fail "remesh an inward obj"
grep -q "^warning: .*tet_in.obj: reversed 1 of 1 closed part" "$tmp/err" || fail "no warning that an inward part was reversed"
cmp -s "$tmp/remesh.stl" "$tmp/remesh_in.stl" || fail "an inward tetrahedron remeshes unlike its outward twin"
# a mesh with no extension, an old Blender header line and '+' signs: read by its content, with warnings
printf 'ply\nformat ascii 1.0\nCreated by Blender 2.49b\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n+0 0 0\n+1 0 0\n0 +1 0\n3 0 1 2\n' >"$tmp/blender_mesh"
"$kizamu" convert "$tmp/blender_mesh" "$tmp/blender.stl" >/dev/null 2>"$tmp/err" || fail "convert a PLY without an extension"
grep -q "^warning: .*content is PLY" "$tmp/err" || fail "no warning that the content decided the format"
grep -q "^warning: .*line 3: header line 'Created by Blender" "$tmp/err" || fail "no warning for the Created by line"
# formats only assimp reads (in the kizamu-import helper beside the executable): COLLADA and glTF
# in, to an ADF; a file assimp cannot read is one line
assimp export "$tmp/tet.obj" "$tmp/tet.dae" >/dev/null 2>&1 || fail "assimp export tet.dae"
"$kizamu" convert "$tmp/tet.dae" "$tmp/dae.kza" --level 5 >/dev/null || fail "convert dae -> kza"
"$kizamu" convert "$tmp/p.glb" "$tmp/p_back.ply" | grep -q "^read .*p.glb: .* $full triangles" || fail "convert glb -> ply"
printf 'not an FBX file\n' >"$tmp/bad.fbx"
"$kizamu" convert "$tmp/bad.fbx" "$tmp/x.obj" >/dev/null 2>"$tmp/err" && fail "a bad FBX should not convert"
[ "$(wc -l <"$tmp/err")" -eq 1 ] && grep -q "bad.fbx: assimp cannot read it" "$tmp/err" || fail "bad FBX: not one line naming assimp"
"$kizamu" convert "$tmp/tet.kza" "$tmp/again.kza" >/dev/null 2>"$tmp/err" && fail "kza -> kza should be refused"
[ "$(wc -l <"$tmp/err")" -eq 1 ] || fail "kza -> kza error is not one line"
"$kizamu" convert "$tmp/half.kza" "$tmp/x.obj" >/dev/null 2>"$tmp/err" && fail "a damaged kza should not convert"
grep -q "truncated" "$tmp/err" || fail "damaged kza -> obj error lacks 'truncated'"

# units: mesh files are millimetres unless --units says otherwise (glTF: metres only, refused
# before any work); 3MF records its unit; --in-units scales a mesh read
maxx() { assimp info "$1" --raw | sed -n 's/^Maximum point *(\([-0-9.e+]*\).*/\1/p'; }
"$kizamu" convert "$tmp/p.kza" "$tmp/p_m.stl" --units m >/dev/null || fail "convert --units m"
python3 -c 'import sys; mm, m = map(float, sys.argv[1:]); assert 0.1 < m < 10 and abs(mm - 1000 * m) < 1e-3 * mm, (mm, m)' \
    "$(maxx "$tmp/p.stl")" "$(maxx "$tmp/p_m.stl")" || fail "the default STL (mm) does not measure 1000 x its --units m export"
"$kizamu" convert "$tmp/p.kza" "$tmp/p_mm.glb" --units mm >"$tmp/out" 2>"$tmp/err" && fail "a glTF in mm should be refused"
grep -q "metres by its specification" "$tmp/err" && [ "$(wc -l <"$tmp/err")" -eq 1 ] && [ ! -s "$tmp/out" ] ||
    fail "glTF --units mm: $(cat "$tmp/err") (stdout: $(cat "$tmp/out"))"
"$kizamu" convert "$tmp/p.kza" "$tmp/p_m.glb" --units m >/dev/null || fail "glTF --units m"
"$kizamu" convert "$tmp/p.kza" "$tmp/p.3mf" >/dev/null || fail "convert kza -> 3mf"
"$kizamu" convert "$tmp/p.kza" "$tmp/p_cm.3mf" --units cm >/dev/null || fail "convert kza -> 3mf --units cm"
vertices=$(assimp info "$tmp/p.glb" --raw | sed -n 's/^Vertices: *\([0-9]*\).*/\1/p')
python3 - "$tmp/p.3mf" "$tmp/p_cm.3mf" "$vertices" <<'PY' || fail "3MF unit or vertex count"
import re, sys, zipfile
for path, unit in ((sys.argv[1], "millimeter"), (sys.argv[2], "centimeter")):
    model = zipfile.ZipFile(path).read("3D/3dmodel.model").decode()
    assert re.search(r'<model [^>]*unit="%s"' % unit, model), path + ": no unit " + unit
    assert model.count("<vertex ") == int(sys.argv[3]), (path, model.count("<vertex "), sys.argv[3])
PY
"$kizamu" convert "$tmp/tet.obj" "$tmp/tet_from_m.stl" --in-units m >/dev/null || fail "convert --in-units m"
[ "$(maxx "$tmp/tet_from_m.stl")" = "1000.000000" ] || fail "a mesh in metres written in mm: max x $(maxx "$tmp/tet_from_m.stl")"
[ "$(maxx "$tmp/tet.stl")" = "1.000000" ] || fail "mm -> mm changed the coordinates: max x $(maxx "$tmp/tet.stl")"
"$kizamu" convert "$tmp/p.kza" "$tmp/x.off" >/dev/null 2>"$tmp/err" && fail "writing .off should be refused"

# run: replay a stroke script; identical bytes twice; a session holds the same clay; bad scripts
repo="$(cd "$(dirname "$0")/../.." && pwd)"
"$kizamu" run "$repo/examples/carve_basics.jsonl" --level 6 --out "$tmp/c1.kza" >/dev/null || fail "run carve_basics"
"$kizamu" run "$repo/examples/carve_basics.jsonl" --level 6 --threads 1 --out "$tmp/c2.kza" >/dev/null || fail "run again"
cmp -s "$tmp/c1.kza" "$tmp/c2.kza" || fail "replaying a script twice gave different bytes"
"$kizamu" run "$repo/examples/carve_basics.jsonl" --level 6 --out "$tmp/c.stl" >/dev/null || fail "run to stl"
admesh "$tmp/c.stl" | grep -q "Edges fixed *: *0" || fail "carved mesh is not closed"
"$kizamu" run "$repo/examples/curves_and_constraints.jsonl" --level 7 --out "$tmp/cc.stl" >/dev/null || fail "run curves_and_constraints"
admesh "$tmp/cc.stl" | grep -q "Edges fixed *: *0" || fail "curves_and_constraints mesh is not closed"
"$kizamu" run "$repo/examples/carve_basics.jsonl" --level 6 --session "$tmp/sess" --checkpoint-every 2 >/dev/null || fail "run --session"
"$kizamu" info "$tmp/sess" | grep -q "strokes     9 " || fail "info on a session: $("$kizamu" info "$tmp/sess")"
"$kizamu" convert "$tmp/sess" "$tmp/s.kza" >/dev/null || fail "convert a session"
# A session corrects the remote field before each checkpoint and journals it, so its clay is
# its own journal's replay, bit for bit.
"$kizamu" run "$tmp/sess/journal.jsonl" --out "$tmp/j.kza" >/dev/null || fail "replay a session's journal"
cmp -s "$tmp/j.kza" "$tmp/s.kza" || fail "the session's clay differs from a replay of its journal"
grep -q '"correct": "all"' "$tmp/sess/journal.jsonl" || fail "the session journal records no corrections"
"$kizamu" run "$repo/examples/carve_basics.jsonl" --session "$tmp/sess" >/dev/null 2>"$tmp/err" && fail "a session must not be overwritten"
printf '%s\n{"op": "carve", "shape": "blob", "radius": 0.1, "path": [[0,0,0]]}\n' "$(head -1 "$repo/examples/carve_basics.jsonl")" >"$tmp/bad.jsonl"
"$kizamu" run "$tmp/bad.jsonl" >/dev/null 2>"$tmp/err"; rc=$?
[ "$rc" -eq 2 ] || fail "a bad script exited $rc, expected 2"
grep -q "bad.jsonl: line 2: unknown tool shape" "$tmp/err" || fail "bad script error: $(cat "$tmp/err")"
[ "$(wc -l <"$tmp/err")" -eq 1 ] || fail "bad script error is not one line"
# live: a trajectory through the live engine; lock step gives the same bytes on every run, and
# the session it journals replays to them; real time works; a bad trajectory is one line
traj="$repo/examples/carve_line.trajectory.jsonl"
"$kizamu" live --trajectory "$traj" --level 6 --rate 0 --out "$tmp/l1.kza" >/dev/null || fail "live --rate 0"
"$kizamu" live --trajectory "$traj" --level 6 --rate 0 --session "$tmp/lsess" --out "$tmp/l2.kza" >/dev/null || fail "live --session"
cmp -s "$tmp/l1.kza" "$tmp/l2.kza" || fail "live --rate 0 gave different bytes on two runs"
"$kizamu" convert "$tmp/lsess" "$tmp/l3.kza" >/dev/null || fail "convert a live session"
cmp -s "$tmp/l1.kza" "$tmp/l3.kza" || fail "the live session's journal does not replay to the live clay"
grep -q '"live"' "$tmp/lsess/journal.jsonl" || fail "the live session's journal has no live record"
"$kizamu" live --trajectory "$repo/examples/sculpt_session.trajectory.jsonl" --level 6 --rate 2000 --out "$tmp/l.stl" >"$tmp/out" ||
    fail "live in real time"
grep -q "strokes" "$tmp/out" || fail "live printed no summary: $(cat "$tmp/out")"
printf '{"kizamu_trajectory": 1, "units": "m"}\n{"t": "x"}\n' >"$tmp/bad.trajectory.jsonl"
"$kizamu" live --trajectory "$tmp/bad.trajectory.jsonl" >/dev/null 2>"$tmp/err" && fail "a bad trajectory was accepted"
[ "$(wc -l <"$tmp/err")" -eq 1 ] || fail "a bad trajectory's error is not one line: $(cat "$tmp/err")"
# live with the simulated stylus: the servo thread, the stylus and the engine in lock step; the
# trace is checked from outside (docs/HAPTIC-TRACE.md); the samples recorded as a trajectory play
# back to the same clay byte for byte; two lock-step runs give the same trace
hand=(live --device sim --hand "$repo/examples/slide_and_carve.hand.jsonl" --level 7 --rate 0)
"$kizamu" "${hand[@]}" --record "$tmp/h.trace.jsonl" --record-trajectory "$tmp/h.trajectory.jsonl" --out "$tmp/h.kza" \
    >"$tmp/out" || fail "live --device sim"
grep -q "in contact" "$tmp/out" || fail "live --device sim printed no summary: $(cat "$tmp/out")"
"$kizamu" "${hand[@]}" --record "$tmp/h2.trace.jsonl" >/dev/null || fail "live --device sim (again)"
cmp -s "$tmp/h.trace.jsonl" "$tmp/h2.trace.jsonl" || fail "two lock-step haptic runs gave different traces"
"$kizamu" live --trajectory "$tmp/h.trajectory.jsonl" --rate 0 --out "$tmp/h3.kza" >/dev/null || fail "play back a recorded device"
cmp -s "$tmp/h.kza" "$tmp/h3.kza" || fail "the recorded device's trajectory does not play back to the same clay"
python3 - "$tmp/h.trace.jsonl" <<'PY' || failures=$((failures + 1))
import json, math, sys
lines = open(sys.argv[1]).read().splitlines()
head = json.loads(lines[0])
for k in ("device", "max_force", "stiffness", "damping", "rate"):
    assert k in head, f"trace header lacks {k}: {head}"
ticks = [json.loads(l) for l in lines[1:]]
assert len(ticks) > 2000, len(ticks)
period = 1.0 / head["rate"]
contact = 0
for i, t in enumerate(ticks):
    for k in ("t", "device", "velocity", "proxy", "force", "contact"):
        assert k in t, f"tick {i} lacks {k}"
    assert abs(t["t"] - i * period) < 1e-9, f"tick {i} at {t['t']}"
    f = math.sqrt(sum(c * c for c in t["force"]))
    assert f <= head["max_force"] + 1e-9, f"tick {i}: |force| {f} above the maximum"
    contact += t["contact"]
    if not t["contact"] and not (t["buttons"] & 1):
        assert f < 1e-12, f"tick {i}: force {f} N out of contact"
assert contact > 500, f"only {contact} ticks in contact"
# Physics from outside: in contact the force is the stiffness times the device-proxy distance
# (no virtual damping here, no friction), up to the clamp and the soft start's ramp.
k = head["stiffness"]
checked = 0
for t in ticks[500:]:
    if t["contact"] and t["t"] > 1.0:
        d = math.sqrt(sum((p - q) ** 2 for p, q in zip(t["proxy"], t["device"])))
        f = math.sqrt(sum(c * c for c in t["force"]))
        if f < head["max_force"] - 1e-6:
            assert abs(f - k * d) < 1e-6 * max(1.0, f), f"t={t['t']}: |force| {f} != K d {k * d}"
            checked += 1
assert checked > 100, checked
PY
"$kizamu" live --device sim >/dev/null 2>"$tmp/err" && fail "live --device sim without --hand was accepted"
grep -q -- "--hand" "$tmp/err" || fail "live --device sim without --hand: unclear error $(cat "$tmp/err")"
# real devices: none here, so each says clearly what is missing; auto falls back to the stylus
for d in falcon hid bogus; do
    "$kizamu" live --device "$d" --seconds 0.2 >/dev/null 2>"$tmp/err" && fail "live --device $d without one was accepted"
    [ "$(wc -l <"$tmp/err")" -eq 1 ] && grep -q -- "--device $d: " "$tmp/err" || fail "live --device $d: unclear error $(cat "$tmp/err")"
done
"$kizamu" live --device auto --hand "$repo/examples/slide_and_carve.hand.jsonl" --level 7 --rate 0 --record "$tmp/h4.trace.jsonl" \
    >/dev/null || fail "live --device auto (no hardware: the simulated stylus)"
cmp -s "$tmp/h.trace.jsonl" "$tmp/h4.trace.jsonl" || fail "live --device auto did not fall back to the simulated stylus"
# progress: a line rewritten with \r on a terminal (script(1) gives the command one), nothing
# when stderr is no terminal or with --quiet; 300 slab strokes at level 7 on one thread take
# about a second, several times the 0.25 s before the first line
head -301 "$repo/examples/slab2000.jsonl" >"$tmp/slab300.jsonl"
slow=("$kizamu" run "$tmp/slab300.jsonl" --level 7 --threads 1 --out "$tmp/slab.3mf" --units cm)
"${slow[@]}" >/dev/null 2>"$tmp/err" || fail "run slab300 --out .3mf"
[ -s "$tmp/err" ] && fail "a run off a terminal wrote to stderr: $(od -c "$tmp/err" | head -3)"
"$kizamu" generate --level 9 --out "$tmp/g.kza" >/dev/null 2>"$tmp/err" || fail "generate level 9"
[ -s "$tmp/err" ] && fail "generate off a terminal wrote to stderr"
if script -qec true /dev/null </dev/null >/dev/null 2>&1; then
    ontty() { script -qec "$(printf '%q ' "$@")" /dev/null </dev/null; }
    ontty "${slow[@]}" >"$tmp/tty" 2>&1 || fail "run on a terminal"
    grep -aq $'\rreplay: [0-9]*/300 strokes' "$tmp/tty" || fail "no progress line on a terminal: $(head -c 300 "$tmp/tty")"
    ontty "${slow[@]}" --quiet >"$tmp/tty" 2>&1 || fail "run --quiet on a terminal"
    grep -aq "replay:" "$tmp/tty" && fail "run --quiet drew progress"
    grep -aq "replayed 300 steps" "$tmp/tty" || fail "run --quiet lost its summary"
    ontty "$kizamu" generate --level 10 --threads 1 --out "$tmp/g.kza" --quiet >"$tmp/tty" 2>&1 || fail "generate --quiet"
    grep -aq "generate:" "$tmp/tty" && fail "generate --quiet drew progress"
    ontty "$kizamu" convert "$tmp/p.stl" "$tmp/p_again.kza" --level 9 --threads 1 --quiet >"$tmp/tty" 2>&1 || fail "convert --quiet"
    grep -aq "generate:" "$tmp/tty" && fail "convert --quiet drew progress"
else
    echo "note: no pseudo-terminal for script(1): progress on a terminal not checked"
fi
# paint: a painted example exported to PLY, GLB and OBJ (run) and via a .kza and a session
# (convert) carries vertex colours that assimp (independent reader) finds: red where the
# example paints red, clay grey elsewhere
"$kizamu" run "$repo/examples/paint.jsonl" --level 7 --out "$tmp/painted.kza" >/dev/null || fail "run paint.jsonl"
"$kizamu" info "$tmp/painted.kza" | grep -q "paint .* points" || fail "info does not report the paint"
"$kizamu" run "$repo/examples/paint.jsonl" --level 7 --session "$tmp/psess" >/dev/null || fail "run paint.jsonl --session"
"$kizamu" convert "$tmp/psess" "$tmp/psess.kza" >/dev/null || fail "convert a painted session"
cmp -s "$tmp/painted.kza" "$tmp/psess.kza" || fail "the painted session's clay (or paint) differs from the plain replay"
for out in painted.ply painted.glb painted.obj; do
    "$kizamu" run "$repo/examples/paint.jsonl" --level 7 --out "$tmp/run_$out" >/dev/null || fail "run paint.jsonl --out $out"
    "$kizamu" convert "$tmp/painted.kza" "$tmp/conv_$out" >/dev/null || fail "convert painted.kza $out"
done
"$kizamu" convert "$tmp/painted.kza" "$tmp/lod_painted.glb" --lod 2 >/dev/null || fail "convert painted.kza --lod"
command -v assimp >/dev/null || fail "assimp (assimp-utils) is required to check exported colours"
for f in run_painted.ply run_painted.glb run_painted.obj conv_painted.ply conv_painted.glb conv_painted.obj lod_painted.glb; do
    assimp dump "$tmp/$f" "$tmp/$f.assxml" >/dev/null 2>&1 || fail "assimp cannot read $f"
    minred=8; [ "$f" = lod_painted.glb ] && minred=1  # flat painted faces have few vertices; a coarse LOD fewer
    python3 - "$tmp/$f.assxml" "$minred" <<'PY' || fail "colours in $f"
import re, sys
text = open(sys.argv[1]).read()
m = re.search(r'<Colors num="(\d+)" set="0" num_components="(\d+)">([^<]*)<', text)
assert m, "no vertex colours"
k = int(m.group(2))
v = [float(x) for x in m.group(3).split()]
def srgb(c):  # glTF stores linear colours
    return 12.92 * c if c <= 0.0031308 else 1.055 * c ** (1 / 2.4) - 0.055
glb = sys.argv[1].endswith(".glb.assxml")
cols = [tuple(round(255 * (srgb(c) if glb else c)) for c in v[i:i + 3]) for i in range(0, len(v), k)]
assert len(cols) == int(m.group(1)), "colour count"
red = sum(1 for c in cols if c == (200, 30, 30))
clay = sum(1 for c in cols if c == (200, 192, 180))
assert red >= int(sys.argv[2]) and clay > len(cols) // 2, f"red {red}, clay {clay} of {len(cols)}"
PY
done
python3 "$repo/scripts/make_slab.py" | cmp -s - "$repo/examples/slab2000.jsonl" || fail "examples/slab2000.jsonl differs from scripts/make_slab.py"

# render: a PNG of the asked size from a .kza, a mesh file and a run's result, off screen (EGL
# surfaceless; Mesa's llvmpipe without a GPU); bad views and sizes are refused before any work
png_size() {  # prints "W H" from a PNG's IHDR, or nothing when the file is not a PNG
    python3 - "$1" <<'PY'
import struct, sys
data = open(sys.argv[1], "rb").read(33)
if data[:8] == b"\x89PNG\r\n\x1a\n" and data[12:16] == b"IHDR":
    print(*struct.unpack(">II", data[16:24]))
PY
}
if [ "$renderer" = norender ]; then
    "$kizamu" --help | grep -q "^ *render " && fail "built without the renderer, but --help lists 'render'"
    "$kizamu" run "$repo/examples/carve_basics.jsonl" --level 6 --render "$tmp/run.png" >/dev/null 2>"$tmp/err" &&
        fail "run --render succeeded without the renderer"
    grep -q "without the renderer" "$tmp/err" || fail "run --render without the renderer: $(cat "$tmp/err")"
else
    export LP_NUM_THREADS=2
    # `kizamu` alone opens the sculpting window; with no display it says so on one line
    env -u DISPLAY "$kizamu" >/dev/null 2>"$tmp/err" && fail "kizamu alone with no display succeeded"
    [ "$(wc -l <"$tmp/err")" -eq 1 ] && grep -q "no display" "$tmp/err" || fail "kizamu alone, no display: $(cat "$tmp/err")"
    "$kizamu" render "$tmp/p.kza" --out "$tmp/p.png" --size 320x200 >"$tmp/out" 2>"$tmp/err" || fail "render kza: $(cat "$tmp/err")"
    [ "$(png_size "$tmp/p.png")" = "320 200" ] || fail "render kza: not a 320x200 PNG: $(png_size "$tmp/p.png")"
    "$kizamu" render "$tmp/tet.obj" --out "$tmp/tet.png" --size 64x48 --view top --mode wireframe --ortho >/dev/null 2>"$tmp/err" ||
        fail "render obj: $(cat "$tmp/err")"
    [ "$(png_size "$tmp/tet.png")" = "64 48" ] || fail "render obj: not a 64x48 PNG"
    "$kizamu" render "$tmp/tet.obj" --out "$tmp/tet6.png" --size 64x64 --level 6 --mode matcap >/dev/null 2>"$tmp/err" ||
        fail "render obj --level: $(cat "$tmp/err")"
    "$kizamu" render "$tmp/p.kza" --out "$tmp/bad.png" --view diagonal >/dev/null 2>"$tmp/err" && fail "render accepted --view diagonal"
    grep -q "view" "$tmp/err" || fail "render's refusal of --view diagonal does not name it: $(cat "$tmp/err")"
    [ -e "$tmp/bad.png" ] && fail "a refused render wrote its PNG"
    "$kizamu" render "$tmp/p.kza" --out "$tmp/bad.png" --size 0x10 >/dev/null 2>&1 && fail "render accepted --size 0x10"
    "$kizamu" render "$tmp/p.kza" --out "$tmp/bad.png" --mode xray >/dev/null 2>&1 && fail "render accepted --mode xray"
    "$kizamu" render "$tmp/p.kza" --out "$tmp/bad.png" --level 6 >/dev/null 2>&1 && fail "render accepted --level for a .kza"
    "$kizamu" run "$repo/examples/carve_basics.jsonl" --level 6 --render "$tmp/run.png" --size 96x64 --view front --ground \
        >/dev/null 2>"$tmp/err" || fail "run --render: $(cat "$tmp/err")"
    [ "$(png_size "$tmp/run.png")" = "96 64" ] || fail "run --render: not a 96x64 PNG"
    mkdir -p "$tmp/shaders" && cp "$repo"/shaders/* "$tmp/shaders/"
    printf '#version 330 core\nout vec4 fragColour;\nvoid main() {\n    fragColour = vec4(nothing);\n}\n' >"$tmp/shaders/clay.frag"
    KIZAMU_SHADER_DIR="$tmp/shaders" "$kizamu" render "$tmp/p.kza" --out "$tmp/bad.png" --size 32x32 >/dev/null 2>"$tmp/err" &&
        fail "render with a corrupt clay.frag succeeded"
    grep -q "shaders/clay.frag:4: error" "$tmp/err" || fail "a corrupt shader's error lacks its file and line: $(cat "$tmp/err")"
    unset LP_NUM_THREADS
fi

# Without the benchmark library there is no `bench` command, and nothing more to check.
if [ "$benchmarks" = nobench ]; then
    "$kizamu" --help | grep -q "^ *bench " && fail "built without the benchmarks, but --help lists 'bench'"
    finish
fi

# bench contract: only JSON objects on stdout, every figure the contract names present
"$kizamu" --help | grep -q "^ *bench " || fail "built with the benchmarks, but --help lacks 'bench'"
"$kizamu" bench adf --json --levels 6,7 --queries 4000 --error-points 2000 --repeats 1 \
    >"$tmp/bench.json" 2>/dev/null || fail "bench adf exited non-zero"
python3 - "$tmp/bench.json" <<'PY' || failures=$((failures + 1))
import json, sys, math
names = {}
for line in open(sys.argv[1]):
    obj = json.loads(line)
    assert set(obj) == {"figure", "value", "unit"}, obj
    names[obj["figure"]] = obj["value"]
need = ["adf.generate_ms.level6", "adf.generate_ms.level7", "adf.cells.level7", "adf.samples.level7",
        "adf.bytes.level7", "adf.bytes_per_cell.level7", "adf.query_coherent_ns.p50",
        "adf.query_coherent_ns.p99", "adf.query_random_ns.p50", "adf.query_random_ns.p99",
        "adf.max_error_in_band.level7"]
missing = [n for n in need if n not in names]
assert not missing, f"missing figures: {missing}"
assert all(isinstance(names[n], (int, float)) and names[n] > 0 for n in need), "non-positive figure"
assert names["adf.max_error_in_band.level7"] <= 1.0, "band error above the bound"
PY
"$kizamu" bench adf --help | grep -q -- "--vs-openvdb" || fail "bench adf --help lacks --vs-openvdb"

# bench mesh contract (small: level 6, one run, the bunny from Debian's CGAL data)
"$kizamu" bench mesh --json --level 6 --repeats 1 \
    >"$tmp/mesh.json" 2>/dev/null || fail "bench mesh exited non-zero"
python3 - "$tmp/mesh.json" <<'PY' || failures=$((failures + 1))
import json, sys
names = {}
for line in open(sys.argv[1]):
    obj = json.loads(line)
    assert set(obj) == {"figure", "value", "unit"}, obj
    names[obj["figure"]] = obj["value"]
need = ["mesh.full_ms.level6", "mesh.full_triangles.level6", "mesh.triangles_per_s", "mesh.lod2k_ms",
        "mesh.lod20k_ms", "mesh.points800k_ms", "mesh.tile_remesh_ms", "mesh.import_ms.bunny.level6",
        "mesh.full_ms.bunny.level6", "mesh.full_triangles.bunny.level6", "mesh.orient_ms.bunny.level6",
        "mesh.lod2k_phase_ms.coarsen",
        "mesh.lod2k_phase_ms.mesh"]
missing = [n for n in need if n not in names]
assert not missing, f"missing figures: {missing}"
assert all(isinstance(names[n], (int, float)) and names[n] > 0 for n in need), "non-positive figure"
PY
"$kizamu" bench mesh --help | grep -q -- "--vs-openvdb" || fail "bench mesh --help lacks --vs-openvdb"

# bench edit contract (small: level 6 dabs, 5 slab strokes at level 6)
"$kizamu" bench edit --json --levels 6 --dabs 3 --slab-strokes 5 --slab-level 6 \
    --slab-script "$repo/examples/slab2000.jsonl" >"$tmp/edit.json" 2>/dev/null || fail "bench edit exited non-zero"
python3 - "$tmp/edit.json" <<'PY' || failures=$((failures + 1))
import json, sys
names = {}
for line in open(sys.argv[1]):
    obj = json.loads(line)
    assert set(obj) == {"figure", "value", "unit"}, obj
    names[obj["figure"]] = obj["value"]
need = ["edit.dab_ms.level6.p50", "edit.dab_remesh_ms.level6.p50", "edit.dab_remesh_ms.level6.p99",
        "edit.undo_ms", "edit.redo_ms", "edit.stroke500_ms.level6", "edit.slab5_s", "edit.slab5_bytes",
        "edit.remesh_phase_ms.crossings.level6.p50", "edit.remesh_phase_ms.vertices.level6.p50",
        "edit.remesh_phase_ms.relax.level6.p50"]
missing = [n for n in need if n not in names]
assert not missing, f"missing figures: {missing}"
assert all(isinstance(names[n], (int, float)) and names[n] > 0 for n in need), "non-positive figure"
PY

# bench live contract (small: 20k pushes, the engine's stroke at level 6 only)
"$kizamu" bench live --json --pushes 20000 --full-pushes 5000 --levels 6 --no-placement --repeats 1 >"$tmp/live.json" 2>/dev/null || fail "bench live exited non-zero"
python3 - "$tmp/live.json" <<'PY' || failures=$((failures + 1))
import json, sys
names = {}
for line in open(sys.argv[1]):
    obj = json.loads(line)
    assert set(obj) == {"figure", "value", "unit"}, obj
    names[obj["figure"]] = obj["value"]
need = ["live.push_us.p50", "live.push_us.p999", "live.push_full_us.p999", "live.sample_to_snapshot_ms.level6.p50",
        "live.sample_to_mesh_ms.level6.p99", "live.segments.level6", "live.vs_whole_stroke.level6"]
missing = [n for n in need if n not in names]
assert not missing, f"missing figures: {missing}"
assert all(isinstance(names[n], (int, float)) and names[n] > 0 for n in need), "non-positive figure"
PY

# bench haptics contract (small: 0.3 s runs, one of each, a level-8 engine)
"$kizamu" bench haptics --json --seconds 0.3 --repeats 1 --level 8 >"$tmp/haptics.json" 2>/dev/null || fail "bench haptics exited non-zero"
python3 - "$tmp/haptics.json" <<'PY' || failures=$((failures + 1))
import json, sys
names = {}
for line in open(sys.argv[1]):
    obj = json.loads(line)
    assert set(obj) == {"figure", "value", "unit"}, obj
    names[obj["figure"]] = obj["value"]
positive = ["haptics.rate_hz", "haptics.period_error_us.p50", "haptics.period_error_us.p99", "haptics.period_error_us.p999",
            "haptics.period_error_us.max", "haptics.force_us.p999", "haptics.bare.period_error_us.p99",
            "haptics.rate_hz.4k", "haptics.period_error_us.4k.p99"]
fractions = ["haptics.missed_deadlines", "haptics.realtime_priority"]
missing = [n for n in positive + fractions if n not in names]
assert not missing, f"missing figures: {missing}"
assert all(isinstance(names[n], (int, float)) and names[n] > 0 for n in positive), "non-positive figure"
assert 0 <= names["haptics.missed_deadlines"] <= 1, "missed deadlines is not a fraction"
assert names["haptics.realtime_priority"] in (0, 1), "realtime_priority is not 0 or 1"
PY
"$kizamu" bench haptics --spin-us 101 --seconds 0.1 >/dev/null 2>&1 && fail "bench haptics accepted a spin above 100 us"
if [ "$renderer" = render ]; then
    # bench render contract (small: 2 frames per mesh, 2 dabs)
    LP_NUM_THREADS=2 "$kizamu" bench render --json --frames 2 --edits 2 >"$tmp/render.json" 2>/dev/null || fail "bench render exited non-zero"
    python3 - "$tmp/render.json" <<'PY' || failures=$((failures + 1))
import json, sys
names = {}
for line in open(sys.argv[1]):
    obj = json.loads(line)
    assert set(obj) == {"figure", "value", "unit"}, obj
    names[obj["figure"]] = obj["value"]
need = ["render.frame_ms.level10", "render.frame_ms.1m_triangles", "render.triangles.1m", "render.draw_calls.level12",
        "render.edit_to_visible_ms", "render.edit_to_mesh_ms", "render.edit_to_visible_frames"]
missing = [n for n in need if n not in names]
assert not missing, f"missing figures: {missing}"
assert all(isinstance(names[n], (int, float)) and names[n] > 0 for n in need), names
assert names["render.triangles.1m"] > 900000, names["render.triangles.1m"]
assert names["render.edit_to_visible_ms"] >= names["render.edit_to_mesh_ms"], names
PY
fi

# devices: exits 0 with or without hardware, always lists the simulated stylus; --json parses
devices=$("$kizamu" devices) || fail "devices exited non-zero"
grep -q "^  sim " <<<"$devices" || fail "devices does not list the simulated stylus: $devices"
"$kizamu" devices --json >"$tmp/devices.json" || fail "devices --json exited non-zero"
python3 - "$tmp/devices.json" <<'PY' || fail "devices --json: not the expected JSON"
import json, sys
d = json.load(open(sys.argv[1]))
assert d["devices"][0]["id"] == "sim" and d["devices"][0]["available"] is True, d
assert isinstance(d["real_devices"], bool) and isinstance(d["notes"], list), d
for dev in d["devices"]:
    assert set(dev) >= {"id", "kind", "name", "available", "status", "axes", "max_force_n"}, dev
PY
finish
