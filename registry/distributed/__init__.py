"""The distributed engine: audits (and, through the same machinery, integral searches)
on a Dask distributed cluster instead of the local worker pool.

``scheduler`` resolves ``--scheduler ADDRESS`` / ``local:N`` / ``REGISTRY_SCHEDULER``
and gives a connected client for one command; ``tasks`` runs picklable calls on the
cluster, each in a child process of a Dask worker, under a deadline, retried
elsewhere when a worker dies; ``audits`` audits cases through it.

Builds on the model, the errors, the mathematics, the case language, the audit and
discovery; never imports the store, the presentation, the API or the command line
(``tests/test_layers.py``): only the client (the API) writes to the database.
"""
