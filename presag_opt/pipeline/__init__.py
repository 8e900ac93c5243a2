"""The decision pipeline: every method that answers "which pre-sag do I build?", gathered once per job.

One orchestrator per command family gathers the evidence and calls
:func:`~presag_opt.design.decision.decide` once: :func:`~presag_opt.pipeline.band.answer_band` for an
operating band on catenary models (``presag recommend``, ``presag robust``, ``presag report``) and
:func:`~presag_opt.pipeline.line.answer_line` for a surveyed line (``presag design``). The report and
the command line only render what they return.
"""
