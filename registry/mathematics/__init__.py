"""The mathematics: the reference paper's mechanics and the decision whether a residual
vanishes (certified evaluation, zero testing), torque families and parameter conditions,
and Kovalevskaya exponents with the Painlevé test (``exponent_analysis``).

Pure sympy: nothing here imports the case language, the audit, the store or the
presentation (``tests/test_layers.py``).
"""
