//! Shared helpers for the cross-check and stability tests.
