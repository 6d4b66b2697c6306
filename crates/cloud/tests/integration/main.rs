//! Integration tests of spatch-cloud (one binary).

mod generated;
