"""Searching for first integrals of a family (registry discover)."""
