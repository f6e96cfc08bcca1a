#!/usr/bin/env python3
"""Self-test of the LoRR 2026 part of tools/check/execution.py (stdlib only, no start kit).

Builds tiny problems (a 4x4 map with one obstacle, 2 agents) and hand-written outputs in a
temporary folder, and checks that the checker accepts the valid ones and rejects each broken one
with the expected message. Run: python3 tools/check/test_execution_lorr2026.py
"""

import json
import os
import subprocess
import sys
import tempfile
import unittest

CHECKER = os.path.join(os.path.dirname(os.path.abspath(__file__)), "execution.py")

MAP = """type octile
height 4
width 4
map
....
.@..
....
....
"""


def segments(actions, size=100, header=None, makespan=None):
    """A kit path string: run-length segments of `size` ticks, every header the start state."""
    makespan = len(actions) if makespan is None else makespan
    out = []
    for k in range(max(1, -(-makespan // size))):
        chunk, runs = actions[k * size:(k + 1) * size], []
        for a in chunk:
            if runs and runs[-1][0] == a:
                runs[-1][1] += 1
            else:
                runs.append([a, 1])
        out.append("[(%d,%s):(%s)]" % (k * size, ",".join(map(str, header)),
                                       ",".join(f"{a} {n}" for a, n in runs)))
    return "".join(out)


class LoRR2026(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.addCleanup(self.dir.cleanup)

    def problem(self, starts, tasks, counter=2, reveal=1.0):
        d = self.dir.name
        with open(os.path.join(d, "m.map"), "w") as f:
            f.write(MAP)
        with open(os.path.join(d, "a.agents"), "w") as f:
            f.write("# agents\n%d\n%s\n" % (len(starts), "\n".join(map(str, starts))))
        with open(os.path.join(d, "t.tasks"), "w") as f:
            f.write("%d\n%s\n" % (len(tasks), "\n".join(",".join(map(str, t)) for t in tasks)))
        prob = {"mapFile": "m.map", "agentFile": "a.agents", "taskFile": "t.tasks",
                "teamSize": len(starts), "numTasksReveal": reveal, "agentCounter": counter,
                "agentSize": 1.0, "version": "2026 LoRR",
                "delayConfig": {"seed": 0, "minDelay": 1, "maxDelay": 1, "eventModel": "bernoulli",
                                "pDelay": 0.0, "durationModel": "uniform", "gaussMeanRatio": 0.5,
                                "gaussStdRatio": 0.2}}
        with open(os.path.join(d, "p.json"), "w") as f:
            json.dump(prob, f)
        self.starts, self.tasks, self.counter = starts, tasks, counter

    def output(self, actions, events=(), schedule=None, finished=0, tasks=None, delays=None,
               makespan=None, planner=True):
        n = len(actions)
        starts = [divmod(s, 4) for s in self.starts]
        out = {"actionModel": "MAPF_T", "version": "2026 LoRR", "teamSize": n,
               "numTaskFinished": finished,
               "makespan": len(actions[0]) if makespan is None else makespan,
               "numPlannerErrors": 0, "numScheduleErrors": 0, "numEntryTimeouts": 0,
               "agentMaxCounter": self.counter, "outputSegmentSize": 100,
               "delayIntervals": delays or [[] for _ in range(n)],
               "start": [[r, c, "E"] for r, c in starts],
               "actualPaths": [segments(a, header=(r, c, 0, 0), makespan=makespan)
                               for a, (r, c) in zip(actions, starts)],
               "events": [list(e) for e in events],
               "tasks": tasks if tasks is not None else []}
        if planner:
            out["plannerPaths"] = list(out["actualPaths"])
            out["errors"] = []
        if schedule is not None:
            out["actualSchedule"] = schedule
        return out

    def run_checker(self, out):
        path = os.path.join(self.dir.name, "out.json")
        with open(path, "w") as f:
            json.dump(out, f)
        proc = subprocess.run([sys.executable, CHECKER, os.path.join(self.dir.name, "p.json"), path],
                              capture_output=True, text=True)
        return proc.returncode, json.loads(proc.stdout)

    def accept(self, out):
        code, res = self.run_checker(out)
        self.assertEqual(code, 0, res)
        self.assertTrue(res["valid"])
        return res

    def reject(self, out, *words):
        code, res = self.run_checker(out)
        self.assertEqual(code, 1, res)
        self.assertFalse(res["valid"])
        for w in words:
            self.assertIn(w, res["reason"])
        return res

    # -- a delivery: agent 0 goes (0,0) -> (0,1) -> (0,3), agent 1 idles (task-less) ----------
    def delivery(self, actions0="FFFFFFWW", **kw):
        self.problem(starts=[0, 15], tasks=[[1, 3], [14, 12], [6, 7]])
        tasks = [[0, 0, [0, 1, 0, 3]], [1, 0, [3, 2, 3, 0]], [2, 6, [1, 2, 1, 3]]]
        args = dict(events=[(2, 0, 0, 1), (6, 0, 0, 2)], schedule=["5:0", "5:-1"], finished=1,
                    tasks=tasks, delays=[[], [[2, 5]]])
        args.update(kw)
        return self.output([actions0, "W" * len(actions0)], **args)

    def test_accepts_a_delivery(self):
        res = self.accept(self.delivery())
        self.assertEqual((res["ticks"], res["tasks_finished"], res["tasks"]), (8, 1, "recounted"))

    def test_wait_pauses_a_forward_mid_edge(self):
        # F, W, F: the F started at tick 0 completes at tick 2 (time 3), not at tick 1
        out = self.delivery("FWFFFFFW", events=[(3, 0, 0, 1), (7, 0, 0, 2)],
                            tasks=[[0, 0, [0, 1, 0, 3]], [1, 0, [3, 2, 3, 0]], [2, 7, [1, 2, 1, 3]]])
        self.accept(out)

    def test_rotation_continues_whatever_is_requested(self):
        # a started R is continued by the F that follows it: R,F = one R, no move
        self.problem(starts=[0, 15], tasks=[[2], [3]])
        out = self.output(["RFWW", "WWWW"], schedule=["0:-1", "0:-1"],
                          tasks=[[0, 0, [0, 2]], [1, 0, [0, 3]]])
        out["plannerPaths"] = [segments("RFWW", header=(0, 0, 0, 0)),
                               segments("WWWW", header=(3, 3, 0, 0))]
        self.accept(out)

    def test_rejects_a_delayed_agent_moving(self):
        out = self.delivery(delays=[[[1, 3]], [[2, 5]]])
        self.reject(out, "tick 1", "agent 0", "delayed")

    def test_rejects_a_wrong_task_count(self):
        self.reject(self.delivery(finished=2), "numTaskFinished is 2", "recount gives 1")

    def test_rejects_an_event_at_the_wrong_time(self):
        self.reject(self.delivery(events=[(3, 0, 0, 1), (6, 0, 0, 2)]), "time 2", "[3, 0, 0, 1]")

    def test_rejects_a_schedule_giving_an_unrevealed_task(self):
        self.reject(self.delivery(schedule=["5:0", "5:-1,2:7"]), "agent 1", "task 7", "not open")

    def test_without_schedule_checks_events_against_movement(self):
        res = self.accept(self.delivery(schedule=None, planner=False))
        self.assertEqual(res["tasks"], "events checked (no actualSchedule)")
        self.reject(self.delivery(schedule=None, planner=False,
                                  events=[(2, 0, 0, 1), (5, 0, 0, 2)]), "time 5", "agent 0")

    def test_unrecorded_ticks_are_placed(self):
        # makespan 10 with 8 recorded ticks: events two ticks later are explained
        out = self.delivery(events=[(4, 0, 0, 1), (8, 0, 0, 2)], makespan=10,
                            tasks=[[0, 0, [0, 1, 0, 3]], [1, 0, [3, 2, 3, 0]], [2, 8, [1, 2, 1, 3]]])
        self.assertEqual(self.accept(out)["unrecorded_ticks"], 2)
        out = self.delivery(events=[(5, 0, 0, 1), (9, 0, 0, 2)], makespan=10,
                            tasks=[[0, 0, [0, 1, 0, 3]], [1, 0, [3, 2, 3, 0]], [2, 9, [1, 2, 1, 3]]])
        self.reject(out, "unrecorded ticks")

    # -- footprints -------------------------------------------------------------------------
    def test_following_is_allowed_overlap_is_not(self):
        self.problem(starts=[9, 8], tasks=[[0]])             # agent 0 at (2,1), agent 1 at (2,0)
        self.accept(self.output(["FFWW", "FFWW"], schedule=["0:-1", "0:-1"], tasks=[[0, 0, [0, 0]], [1, 0, [0, 0]]]))
        self.reject(self.output(["WWWW", "FFWW"], schedule=["0:-1", "0:-1"], tasks=[[0, 0, [0, 0]], [1, 0, [0, 0]]]),
                    "tick 0", "agents 0 and 1", "overlap")

    def test_rejects_a_swap_caught_only_by_the_sweep(self):
        self.problem(starts=[0, 1], tasks=[[12]], counter=1)  # (0,0) and (0,1), one tick per F
        # agent 1 turns to face west, then both step forward: they swap cells; the end positions
        # do not overlap, the motions do
        out = self.output(["WWFW", "CCFW"], schedule=["0:-1", "0:-1"], tasks=[[0, 0, [3, 0]], [1, 0, [3, 0]]])
        self.reject(out, "tick 2", "agents 0 and 1", "collide during the tick")

    def test_rejects_a_forward_into_an_obstacle(self):
        self.problem(starts=[4, 15], tasks=[[0]])             # agent 0 at (1,0), '@' at (1,1)
        self.reject(self.output(["WFFW", "WWWW"], schedule=["0:-1", "0:-1"], tasks=[[0, 0, [0, 0]], [1, 0, [0, 0]]]),
                    "tick 1", "agent 0", "obstacle cell [1, 1]")

    def test_rejects_a_forward_off_the_map(self):
        self.problem(starts=[3, 15], tasks=[[0]])             # agent 0 at (0,3) facing east
        self.reject(self.output(["FFWW", "WWWW"], schedule=["0:-1", "0:-1"], tasks=[[0, 0, [0, 0]], [1, 0, [0, 0]]]),
                    "tick 0", "agent 0", "leaves the map")

    def test_rejects_an_action_the_planner_did_not_request(self):
        out = self.delivery()
        out["plannerPaths"][0] = segments("WWWWWWWW", header=(0, 0, 0, 0))
        self.reject(out, "tick 0", "agent 0", "planner action was W")

    def test_rejects_another_version(self):
        out = self.delivery()
        out["version"] = "2024 LoRR"
        self.reject(out, "2024 LoRR")


if __name__ == "__main__":
    unittest.main()
