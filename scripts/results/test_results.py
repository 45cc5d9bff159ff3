"""Unit tests of the results program's pure parts: `python3 -m unittest discover -s scripts/results`
(CI runs them)."""

import os
import sys
import tempfile
import unittest

# The sections read their settings from the environment when imported.
os.environ.setdefault("WOGAN", "wogan")
os.environ.setdefault("SEEDS", "1 2")
os.environ.setdefault("ORACLES", "beamng-ai-proxy dave2-proxy")
os.environ.setdefault("WORK", tempfile.gettempdir())
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from benches import duration  # noqa: E402
from common import median, num, split  # noqa: E402
from field import rounded  # noqa: E402
from missing import how_to_make, missing_runs  # noqa: E402
from page import LOG_HEADING, splice  # noqa: E402

OLD = """# Results

Old intro.

- date: 2026-11-24
- sections ci regenerated on 2026-11-25

## A

old a

## B

old b

### dave2-proxy

old b dave2

### beamng-ai-proxy

old b beamng

## Figures from earlier sessions

earlier
"""


class SpliceTest(unittest.TestCase):
    def test_a_section_is_replaced_in_place_and_old_stamps_move_to_the_log(self):
        text = splice(OLD, ["## A", "", "new a", ""], "- sections a regenerated", False)
        lines = text.split("\n")
        self.assertEqual(lines[0], "# Results")
        self.assertNotIn("Old intro.", lines)
        self.assertLess(lines.index("## A"), lines.index("new a"))
        self.assertNotIn("old a", lines)
        self.assertIn("old b", lines)
        log = lines[lines.index(LOG_HEADING):]
        self.assertEqual(log[2:5], ["- date: 2026-11-24", "- sections ci regenerated on 2026-11-25",
                                    "- sections a regenerated"])
        # Nothing but the title and the intro is above the first section.
        self.assertFalse(any(line.startswith("- ") for line in lines[:lines.index("## A")]))

    def test_a_new_section_goes_before_the_earlier_figures_and_the_log(self):
        once = splice(OLD, ["## C", "", "new c"], "- one", False)
        twice = splice(once, ["## D", "", "new d"], "- two", False).split("\n")
        self.assertLess(twice.index("## C"), twice.index("## Figures from earlier sessions"))
        self.assertLess(twice.index("## D"), twice.index("## Figures from earlier sessions"))
        self.assertEqual(twice[-3:], ["- one", "- two", ""])
        self.assertEqual(twice.count(LOG_HEADING), 1)

    def test_narrowed_keeps_the_other_drivers_subsections(self):
        fresh = ["## B", "", "intro", "", "### dave2-proxy", "", "new b dave2", ""]
        lines = splice(OLD, fresh, "- b", True).split("\n")
        self.assertIn("new b dave2", lines)
        self.assertNotIn("old b dave2", lines)
        self.assertIn("old b beamng", lines)


    def test_a_page_without_a_log_gets_one_at_the_end(self):
        text = splice("# Results\n\n## A\n\nold a\n", ["## A", "", "new a"], "- a again", False)
        self.assertTrue(text.endswith(f"{LOG_HEADING}\n\n- a again\n"))
        self.assertEqual(text.count("## "), 2)


class SplitTest(unittest.TestCase):
    def test_blocks_start_at_each_heading(self):
        head, blocks = split(["t", "## x", "1", "## y", "2"], "## ")
        self.assertEqual(head, ["t"])
        self.assertEqual(blocks, [["## x", "1"], ["## y", "2"]])


class MissingTest(unittest.TestCase):
    def test_absent_runs_are_listed_with_the_commands_that_make_them(self):
        with tempfile.TemporaryDirectory() as root:
            here = os.getcwd()
            os.chdir(root)
            try:
                os.makedirs("target/effectiveness")
                open("target/effectiveness/dave2-proxy.paper.wogan.1.jsonl", "w").close()
                missing = missing_runs(["dave2-proxy"], ["1", "2"], [["paper", "wogan"]])
            finally:
                os.chdir(here)
        self.assertEqual(missing, ["dave2-proxy paper seeds 2", "dave2-proxy stgem seeds 1 2"])
        commands = how_to_make(missing, ["1", "2"])
        self.assertEqual(commands[0], '  SEEDS="1 2" ORACLES=dave2-proxy SETS=paper scripts/runs/search_figures.sh')
        self.assertIn("stgem_search.py --oracle dave2-proxy --seeds 1,2", commands[1])

    def test_every_search_command_comes_before_stgems_and_all_seeds_need_no_seeds_variable(self):
        missing = ["beamng-ai-proxy paper seeds 3", "beamng-ai-proxy stgem seeds 3",
                   "dave2-proxy random seeds 3 4", "dave2-proxy stgem seeds 4"]
        commands = how_to_make(missing, [str(s) for s in range(1, 21)])
        self.assertEqual(commands[:2], ["  ORACLES=beamng-ai-proxy SETS=paper scripts/runs/search_figures.sh",
                                        "  ORACLES=dave2-proxy SETS=random scripts/runs/search_figures.sh"])
        self.assertIn("--oracle beamng-ai-proxy --seeds 3 ", commands[2])
        self.assertIn("--oracle dave2-proxy --seeds 4 ", commands[3])


class FiguresTest(unittest.TestCase):
    def test_num_drops_trailing_zeros_and_groups_thousands(self):
        self.assertEqual(num(2.0), "2")
        self.assertEqual(num(2.25, 2), "2.25")
        self.assertEqual(num(0.0), "0")
        self.assertEqual(num(12345.04), "12,345")
        self.assertEqual(num(1500), "1,500")
        self.assertEqual(num(None), "–")

    def test_median_of_nothing_is_none(self):
        self.assertIsNone(median([]))
        self.assertEqual(median([3, 1, 2, 10]), 2.5)

    def test_rounded_keeps_what_is_not_a_number(self):
        self.assertEqual(rounded("1,234.567"), "1,234.6")
        self.assertEqual(rounded("3.000"), "3")
        self.assertEqual(rounded("–"), "–")

    def test_duration_picks_the_unit(self):
        self.assertEqual(duration(None), "–")
        self.assertEqual(duration(512), "512 ns")
        self.assertEqual(duration(2_500), "2.5 µs")
        self.assertEqual(duration(12_340_000), "12.3 ms")
        self.assertEqual(duration(3e9), "3 s")


if __name__ == "__main__":
    unittest.main()
