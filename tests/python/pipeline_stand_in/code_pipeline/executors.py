"""A small stand-in for the pipeline's code_pipeline.executors, so that an executor written for the
pipeline can be tested without a checkout of it. It keeps only the behaviour an executor relies on:
execute_test() calls _execute(), charges the last record's `timer` to the execution budget and
stores the outcome; the base _execute() refuses to run when no budget is left (sys.exit(123), as
the pipeline does). No road validation, no files, no generation-time accounting.
"""
import sys
import types
from abc import ABC, abstractmethod


class AbstractTestExecutor(ABC):

    def __init__(self, result_folder, map_size, generation_budget=None, execution_budget=None,
                 time_budget=None, road_visualizer=None, debug=False):
        self.result_folder = result_folder
        self.map_size = map_size
        self.debug = debug
        # Simulated seconds left; None means unlimited.
        self.remaining_execution_budget = execution_budget
        # The budgets as given, where the pipeline keeps them (its Budget object).
        self.time_budget = types.SimpleNamespace(generation_budget=generation_budget,
                                                 execution_budget=execution_budget,
                                                 time_budget=time_budget)
        self.timeout_forced = False
        self.budget_checks = 0  # how often the base _execute() was reached
        self.results = []  # (test id, outcome, description, execution_data) per executed test
        self.closed = False

    def _budget_left(self):
        return self.remaining_execution_budget is None or self.remaining_execution_budget > 0

    def execute_test(self, the_test):
        outcome, description, execution_data = self._execute(the_test)
        if execution_data:
            if self.remaining_execution_budget is not None:
                self.remaining_execution_budget -= execution_data[-1].timer
            if not self._budget_left():
                self.timeout_forced = True
                sys.exit(123)
        self.results.append((the_test.id, outcome, description, execution_data))
        return outcome, description, execution_data

    def is_force_timeout(self):
        return self.timeout_forced

    def is_over(self):
        return not self._budget_left()

    def close(self):
        self._close()

    @abstractmethod
    def _execute(self, the_test):
        self.budget_checks += 1
        if not self._budget_left():
            self.timeout_forced = True
            sys.exit(123)

    @abstractmethod
    def _close(self):
        self.closed = True
