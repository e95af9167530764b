"""The registry's runs: the policies behind the facade's verbs.

An audit run that reuses stored results (``audit_run``), a search run that records and
reuses searches (``search_run``), and a run's interruption (``interruption``): a signal
ends a run as Ctrl-C does, never in the middle of a database session. ``api.Registry``
delegates to these; the command line talks only to the facade (``api``).
"""
