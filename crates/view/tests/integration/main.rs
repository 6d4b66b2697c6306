//! The viewer's frame loop driven by scripted events.

mod frame_loop;
