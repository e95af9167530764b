"""The registry's tests: a package, so that test modules are named by their place
(``tests.store.test_database``) and share code only through ``tests.helpers``."""
