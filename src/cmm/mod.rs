//! Reading CMM exports (`shared/spec/cmm-csv.md`) and matching points to the nominal part.
