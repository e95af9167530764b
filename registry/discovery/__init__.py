"""Searching for first integrals of a family (``registry discover``).

``search.discover`` finds the polynomial integrals of weighted degree <= K of a
case (``ansatz``), and, for a family, the values of its free parameters where more
appear (``locus``); the linear algebra runs over Q, Q(p) or modulo a prime
(``linear``), extra integrals are counted modulo the known ones (``integrals``) and
written in their simplest form (``simplest_form``).
"""
