#!/usr/bin/env python3
"""check_suite.py's bars on made-up outputs: one map scored whole, and several maps scored as a
survey (every true object found somewhere, each object's own precision and recall)."""
import json
import os
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.dont_write_bytecode = True  # no __pycache__ in the source tree
sys.path.insert(0, HERE)
import check_suite  # noqa: E402

SCENARIO = """name: pair
meshes:
  - {file: meshes/a.obj, role: object}
  - {file: meshes/b.obj, role: object}
  - {file: meshes/s.obj, role: seabed}
"""


def metrics(p, r, objects):
    return {"precision": p, "recall_visible": r, "chamfer_cm": 3.0, "counts": {"objects": objects}}


def survey_object(name, map_id, p, r, found=True):
    return {"name": name, "found": found, "map_id": map_id if found else None, "precision": p if found else None,
            "recall_visible": r if found else None, "chamfer_cm": 3.0}


class CheckSuite(unittest.TestCase):
    def run_check(self, fused_objects, survey=None):
        with tempfile.TemporaryDirectory() as d:
            scenario = os.path.join(d, "pair.yaml")
            with open(scenario, "w") as f:
                f.write(SCENARIO)
            expectations = os.path.join(d, "expectations.yaml")
            with open(expectations, "w") as f:
                f.write("pair: 2\n")
            out = os.path.join(d, "out")
            os.makedirs(out)
            steps = [{"name": "sf-sim", "rc": 0, "seconds": 1.0, "message": ""}]
            report = {"objects_true": 2, "variants": {
                "fls_only": metrics(0.3, 0.9, 5), "carve_only": metrics(0.8, 0.6, 1),
                "paper": metrics(0.1, 1.0, 1), "fused": metrics(0.95, 0.95, fused_objects)}}
            if survey is not None:
                steps.append({"name": "sf-eval survey", "rc": 0, "seconds": 1.0, "message": ""})
                with open(os.path.join(out, "survey.json"), "w") as f:
                    json.dump(survey, f)
            with open(os.path.join(out, "steps.json"), "w") as f:
                json.dump({"scenario": scenario, "seconds": 2.0, "steps": steps}, f)
            with open(os.path.join(out, "report.json"), "w") as f:
                json.dump(report, f)
            rc = check_suite.check(scenario, out, expectations)
            with open(os.path.join(out, "check.json")) as f:
                return rc, json.load(f)

    @staticmethod
    def survey(objects, maps=2):
        found = sum(o["found"] for o in objects)
        return {"mode": "survey", "objects": objects,
                "detection": {"true": len(objects), "found": found, "false": 0, "duplicates": 0,
                              "predicted": found, "maps": maps}}

    def test_one_map_counts_the_objects_it_holds(self):
        rc, res = self.run_check(fused_objects=1)
        self.assertEqual(rc, 1)
        self.assertTrue(any(f.startswith("detected: fused objects 1") for f in res["failures"]), res["failures"])
        self.assertEqual(self.run_check(fused_objects=2)[0], 0)

    def test_objects_in_two_maps_are_all_detected(self):
        survey = self.survey([survey_object("a", 1, 0.95, 0.97), survey_object("b", 2, 0.9, 0.88)])
        rc, res = self.run_check(fused_objects=1, survey=survey)
        self.assertEqual(rc, 0, res["failures"])
        self.assertEqual(res["survey"]["detection"]["found"], 2)

    def test_an_object_no_map_holds_is_missed(self):
        survey = self.survey([survey_object("a", 1, 0.95, 0.97), survey_object("b", 2, 0, 0, found=False)])
        rc, res = self.run_check(fused_objects=1, survey=survey)
        self.assertEqual(rc, 1)
        self.assertTrue(any("found 1 of 2" in f for f in res["failures"]), res["failures"])

    def test_each_object_meets_the_bars_in_its_own_map(self):
        survey = self.survey([survey_object("a", 1, 0.95, 0.97), survey_object("b", 2, 0.80, 0.90)])
        rc, res = self.run_check(fused_objects=1, survey=survey)
        self.assertEqual(rc, 1)
        self.assertEqual(res["failures"], ["fused precision of b (map 2) 0.800 (bar 0.85)"])

    def test_an_unreadable_survey_report_fails(self):
        rc, res = self.run_check(fused_objects=2, survey={"mode": "maps"})
        self.assertEqual(rc, 1)
        self.assertTrue(any(f.startswith("survey scoring of the fused maps") for f in res["failures"]), res["failures"])


if __name__ == "__main__":
    unittest.main()
