"""Identification of a system with the catalog's cases: which cases have the same vector
field after substituting parameter values, under the equivalences the literature uses
(``identify``), and which of their claims an integral found equals (``claim_match``).
"""
