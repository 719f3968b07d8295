#!/bin/bash
# The library's searches on today's physics (the library-refresh issue), in lanes that each
# keep one core busy; run from the repository root, in the background:
#
#     nohup tools/library_searches.sh frog > /dev/null 2>&1 &
#     nohup nice -n 10 tools/library_searches.sh eel3d > /dev/null 2>&1 &
#     nohup nice -n 10 tools/library_searches.sh straight-3d > /dev/null 2>&1 &
#
# The frog's searches are the longest chain (its straight gait, then its pitches from it,
# 10-15 core-hours each), so its lane keeps a core to itself and the others share the
# second at a lower priority. Once the frog's straight gait ships, its lane frog-pitches
# runs its two pitches side by side; once another creature's ships, its manoeuvres start
# in a lane of their own (nohup nice -n 10 tools/library_searches.sh maneuvers manta, or
# its two pitches side by side: tools/library_searches.sh pitches manta).
#
# Each search runs in runs/NAME with its log in runs/NAME.log, one worker, seed 1, the
# default search. A search whose run directory holds a checkpoint goes on from it
# (--resume); one that has finished (gait.json written) is skipped. runs/ does not outlive
# a session's machine, so each search's best so far is carried into the repository every
# CARRY_EVERY seconds (900) and when it ends (python tools/carry_searches.py; commit
# tools/carried/ before the session ends, and carry once more by hand): a search with no
# checkpoint goes on from its last carried leg, and one whose last leg finished it is
# skipped, so the same command picks up where the last session stopped. Ship a finished
# search's gait with tools/ship_gait.py once the slow tests pass with it; the manoeuvre and
# efficiency lanes start from the shipped straight gait, so run them after the straight
# gaits have shipped.
set -u
cd "$(dirname "$0")/.."
CARRY_EVERY=${CARRY_EVERY:-900}  # seconds between legs written while a search runs

search() {  # run directory name, then aquagait optimize's arguments
    local out=$1
    shift
    if [ -f "runs/$out/gait.json" ]; then
        echo "runs/$out: finished, skipped"
        return
    fi
    local more status
    more=$(python tools/carry_searches.py --continue "$out")
    status=$?
    if [ $status -eq 3 ]; then
        echo "runs/$out: finished (its last leg in tools/carried), skipped"
        return
    elif [ $status -ne 0 ]; then
        echo "runs/$out: cannot tell how to go on (tools/carry_searches.py --continue $out)" >&2
        return
    fi
    # shellcheck disable=SC2206  # carry_searches prints plain words (flags, a path, numbers)
    local continuing=($more)
    echo "runs/$out: aquagait optimize $* ${continuing[*]}"
    mkdir -p runs
    aquagait optimize "$@" --seed 1 --workers 1 --out "runs/$out" "${continuing[@]}" \
        >> "runs/$out.log" 2>&1 &
    local pid=$! waited=0
    while kill -0 $pid 2>/dev/null; do  # carried every CARRY_EVERY s, and at its end
        sleep 30
        waited=$((waited + 30))
        if [ $waited -ge "$CARRY_EVERY" ]; then
            python tools/carry_searches.py "runs/$out" >> "runs/$out.log" 2>&1
            waited=0
        fi
    done
    wait $pid
    python tools/carry_searches.py "runs/$out" >> "runs/$out.log" 2>&1
}

from_both_starts() {  # each creature from its shipped straight gait, then each from hand-set
    local name
    for name in "$@"; do search "$name-straight-51" "$name"; done
    for name in "$@"; do search "$name-handset-51" "$name" --start hand-set; done
}

pitches_side_by_side() {  # a creature's pitch-up and pitch-down at once, one core each
    search "$1-pitch-up-51" "$1" --maneuver pitch-up &
    search "$1-pitch-down-51" "$1" --maneuver pitch-down &
    wait
}

usage() {
    echo "usage: $0 eel3d|straight-3d|frog|maneuvers [CREATURE ...]|frog-pitches|pitches CREATURE|efficient [CREATURE ...]" >&2
    exit 2
}

case "${1:-}" in
eel3d)  # the 2D creatures' straight searches (eel2d's and turtle2d's from both starts,
    # accordion2d's) finished and shipped on 2026-12-06: this lane was straight-2d
    from_both_starts eel3d
    ;;
straight-3d)
    from_both_starts manta turtle3d alien
    ;;
frog)  # its shipped straight gait is the hand-set kick with searched forelimbs: one start
    search frog-straight-51 frog
    ;;
maneuvers)  # from the shipped straight gaits, the manta's capped by its side-car (0.25 rad);
    # name creatures to learn only theirs (tools/library_searches.sh maneuvers manta), as
    # each straight gait ships. eel2d's turns shipped on 2026-12-06 and turtle2d's on
    # 2026-12-07 (its legs say finished), so only the manta's are left by default
    shift
    names=("$@")
    [ ${#names[@]} -eq 0 ] && names=(manta)
    for name in "${names[@]}"; do
        moves=(turn-left turn-right)
        [ "$name" = manta ] && moves=(pitch-up pitch-down)
        for move in "${moves[@]}"; do search "$name-$move-51" "$name" --maneuver "$move"; done
    done
    ;;
frog-pitches)  # the frog's manoeuvres: pitches, which keep its mirror (a turn would drop
    # it and double the parameters); it follows a vertical S with them, as the manta does
    pitches_side_by_side frog
    ;;
pitches)  # one creature's two pitches side by side (tools/library_searches.sh pitches manta)
    [ $# -eq 2 ] || usage
    pitches_side_by_side "$2"
    ;;
efficient)  # at 75 % of the shipped straight gait's cruising speed (the default); name
    # creatures to search only theirs (tools/library_searches.sh efficient eel2d fish), as
    # each straight gait ships
    shift
    names=("$@")
    [ ${#names[@]} -eq 0 ] && names=(eel2d eel3d fish)
    for name in "${names[@]}"; do
        cycles=6
        [ "$name" = fish ] && cycles=12  # the fish takes longer to reach cruise
        search "$name-efficient-51" "$name" --objective efficiency --cycles "$cycles"
    done
    ;;
*)
    usage
    ;;
esac
