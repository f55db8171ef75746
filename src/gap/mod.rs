//! The sim-to-real gap: candidate unmodelled effects (`shared/spec/effects.md`) and diagnosis.
