//! Integration tests of spatch-scan.
//!
//! - `bunny_conf`: the ten Stanford bunny scans through `bun.conf` line up (skips without
//!   ../shared/data).

mod bunny_conf;
