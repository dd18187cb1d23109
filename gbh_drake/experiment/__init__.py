"""The paper's experiment (Table 1) in simulation: objects x trials x methods, from one YAML file.

``gbh experiment EXPERIMENT.yaml [--workers N] [--ray ADDRESS]`` runs it (``scenarios/
experiment.yaml``: the whole object set, 5 trials, four methods; ``scenarios/
experiment_small.yaml``: a quick look), ``gbh report DIR`` rebuilds its tables and plot from the
rows. Every trial's seed comes from (seed, object, trial) alone: every method sees the same poses,
and the rows are the same whatever the order, the number of workers or the engine (timing fields
aside). The parts, each a small module:

* :mod:`~gbh_drake.experiment.config`: the experiment file (:class:`Experiment`, the methods as
  YAML overrides of a base scenario), the seed of each trial from (seed, object, trial) alone, and
  the list of :class:`~gbh_drake.experiment.task.TrialTask`;
* :mod:`~gbh_drake.experiment.worker`: one trial in a worker process (a row, and a Meshcat replay
  when it failed);
* :mod:`~gbh_drake.experiment.engines`: where the trials run: local worker processes or Ray tasks;
* :mod:`~gbh_drake.experiment.rows`: the JSONL rows (append, resume, compare timing aside);
* :mod:`~gbh_drake.experiment.runner`: resume, run, write, report;
* :mod:`~gbh_drake.experiment.report`: ``summary.md`` (Table 1 beside the paper's, per object,
  failures), ``trials.csv``, ``table1.csv``, ``success.png``/``.svg`` and ``causes.png``/``.svg``;
* :mod:`~gbh_drake.experiment.stats`: Wilson intervals, McNemar's exact test, Holm;
* :mod:`~gbh_drake.experiment.taxonomy`: one cause class per failed trial (``cause_of``).

This package's ``__init__`` imports nothing heavy: worker processes import it before they set
their thread count.
"""
