//! Generated clouds: planes, spheres.
