//! The grouped Phong resolve pass against shading each pixel alone, on
//! bands of random pixels of every kind (see [`check_phong_resolve`]),
//! and the resolve of a band's box against the whole band's.

use glam::Vec3;

use crate::fixed::Z_FAR;
use crate::isa::Isa;
use crate::lighting::{unpack_normal, unpack_rgb, Material, ShadeFrame};
use crate::options::Shading;
use crate::plan::work::{ChunkWork, Item};
use crate::raster::band::{Sample, PATCH_SAMPLE};
use crate::raster::band_box::PixelBox;
use crate::shade::phong_items::PhongItems;
use crate::shade::resolve::{phong_reference, resolve_band, resolve_box, Resolve};
use crate::shade::rgba::to_rgba8;
use crate::test_rng::XorShift;

/// Two 9 × 9 patches with colours, bumpy, with a few empty nodes.
fn coloured_scene(rng: &mut XorShift) -> crate::prepare::scene::PreparedScene {
    use spatch_format::{ColourChannel, Frame, GridSize, Patch, Scene};
    let patches = (0..2)
        .map(|p| {
            let frame = Frame::new(
                glam::Vec3::new(p as f32 * 9.0, 0.0, 0.0),
                glam::Vec3::X,
                glam::Vec3::Y * (1.0 + p as f32),
                glam::Vec3::Z * 0.01,
            )
            .unwrap();
            let d = (0..81)
                .map(|k| {
                    if k % 23 == 7 {
                        spatch_format::EMPTY
                    } else {
                        rng.below(3000) as u16
                    }
                })
                .collect();
            let c = (0..81)
                .map(|_| [0, 1, 2, 3].map(|_| rng.below(256) as u8))
                .collect();
            Patch::new(frame, GridSize::new(9, 9).unwrap(), d, Some(c)).unwrap()
        })
        .collect();
    let scene = Scene::new(glam::DVec3::ZERO, ColourChannel::Rgba8, patches).unwrap();
    crate::prepare::scene::PreparedScene::new(&scene)
}

/// Which pixels [`check_phong_resolve`] draws.
#[derive(Clone, Copy)]
enum Mix {
    /// Every kind of pixel: empty, triangle samples, patch samples of
    /// items with and without colours.
    Everything,
    /// Nearly all patch samples of items without colours, of both
    /// shade frames (the fast path of [`resolve_group`]).
    Uncoloured,
    /// Items without colours only (a frame without colours: the fast
    /// path does not look at the items' albedos), patch samples of
    /// both shade frames and a few triangle samples.
    NoColours,
    /// Nearly all patch samples of items with colours, of both shade
    /// frames (the coloured path of [`resolve_group`]).
    Coloured,
}

#[test]
fn phong_resolve_matches_scalar_shading_per_pixel() {
    // Shininess 32 takes the five squarings of `resolve_phong_pixels`.
    // Four pixels at a time, and eight with AVX2 where the CPU has it.
    for isa in [Isa::Base, Isa::detect(true)] {
        check_phong_resolve(Mix::Everything, (61, 7), isa);
        check_phong_resolve(Mix::Everything, (62, 32), isa);
        check_phong_resolve(Mix::Uncoloured, (64, 32), isa);
        check_phong_resolve(Mix::Uncoloured, (63, 7), isa);
        check_phong_resolve(Mix::NoColours, (64, 32), isa);
        check_phong_resolve(Mix::NoColours, (65, 7), isa);
        check_phong_resolve(Mix::Coloured, (64, 32), isa);
        check_phong_resolve(Mix::Coloured, (66, 7), isa);
    }
}

/// Resolves a band of `width × 6` random pixels of `mix`, lit with
/// `shininess`, with the kernels of `isa`, and checks every pixel against
/// [`phong_reference`] or [`Material::shade`].
fn check_phong_resolve(mix: Mix, (width, shininess): (i32, u32), isa: Isa) {
    let mut rng = XorShift(0x9e37_79b9_7f4a_7c15);
    let prepared = coloured_scene(&mut rng);
    let patches = &prepared.patches;
    assert_eq!(patches.len(), 2);
    assert!(patches.iter().all(|p| p.level_count() >= 2));
    // Pieces at levels 0 and 1, cut in several ways, with and without
    // their colours, and level-1 pieces shaded from level 0.
    let mut chunk = ChunkWork::default();
    for k in 0..8u32 {
        let (frame, level) = ((k % 2) as usize, (k / 2 % 2) as usize);
        let lc = patches[frame].level(level).cols;
        let (i0, j0) = if level == 0 {
            (k as usize % 3, 1)
        } else {
            (0, 0)
        };
        chunk.items.push(Item {
            first: 0,
            cols: (lc - i0) as u16,
            rows: (lc - j0) as u16,
            nu: [1, 2, 3, 5][k as usize % 4],
            nv: [1, 4, 2, 3][k as usize / 2 % 4],
            frame: frame as u32,
            flags: 0,
            spans: 0,
            uniform_albedo: k >= 4 || matches!(mix, Mix::NoColours),
            level: level as u8,
            // Two whole level-1 pieces shaded from level 0 (coarse geometry).
            shade_shift: (level == 1 && k >= 6) as u8,
            i0: i0 as u16,
            j0: j0 as u16,
            y0: 0,
            y1: 0,
            x0: 0,
            x1: 0,
            z_near: i32::MIN,
            inside_columns: false,
            splat: [0, 0],
            open_sides: false,
            centres: None,
        });
    }
    let items: Vec<(u32, u32)> = (0..8).map(|i| (0, i)).collect();
    let chunks = [chunk];
    let lighting = crate::Lighting {
        shininess,
        ..Default::default()
    };
    let light = crate::lighting::WorldLight::new(
        &lighting,
        [glam::DVec3::X, glam::DVec3::Y, glam::DVec3::Z],
    );
    let frames: Vec<ShadeFrame> = patches
        .iter()
        .enumerate()
        .map(|(k, p)| light.frame_in(&p.rotation, (k == 1).then(|| -p.rotation.z_axis)))
        .collect();
    let phong = PhongItems::new(Shading::Phong, &items, &chunks, patches, &frames);
    assert_eq!(phong.uncoloured, matches!(mix, Mix::NoColours));
    let r = Resolve {
        shading: Shading::Phong,
        items: &items,
        chunks: &chunks,
        phong: &phong,
        patches: &[],
        material: Material::new(&lighting),
        base_albedo: Vec3::new(200.0, 120.0, 40.0),
        background: [1, 2, 3, 4],
        near: 0.5,
        far: 10.0,
        isa,
    };
    let rows = 6;
    let mut band = vec![Sample::EMPTY; (rows * width) as usize];
    let mut expected = Vec::new();
    for px in band.iter_mut() {
        let choice = match mix {
            Mix::Everything => rng.below(10),
            Mix::Uncoloured | Mix::Coloured => {
                [0, 9, 9, 9, 9, 9, 9, 9, 9, 9, 9, 9, 9, 9, 9, 9][rng.below(16) as usize]
            }
            Mix::NoColours => {
                [0, 1, 9, 9, 9, 9, 9, 9, 9, 9, 9, 9, 9, 9, 9, 9][rng.below(16) as usize]
            }
        };
        if choice == 0 {
            expected.push(r.background);
            continue;
        }
        px.depth = rng.below(Z_FAR as u32) as i32;
        if choice == 1 {
            // A triangle sample with its own normal, albedo and frame.
            let n = Vec3::new(rng.below(200) as f32, rng.below(200) as f32, 100.0);
            let normal = crate::lighting::pack_normal((n - Vec3::new(100.0, 100.0, 0.0)) / 200.0);
            px.w1 = rng.next_u32() & 0xff_ffff;
            px.set_words(normal, rng.below(2));
            let c = r.material.shade(
                unpack_normal(px.w0()),
                &frames[px.w2() as usize],
                unpack_rgb(px.w1),
            );
            expected.push(to_rgba8(c));
            continue;
        }
        // Runs of one item, as drawn patches leave them, or any item
        // (`Mix::Uncoloured`: an item without colours, runs of one).
        let id = match mix {
            Mix::Everything if choice < 6 => 3,
            Mix::Everything => rng.below(8),
            Mix::Uncoloured if rng.below(3) == 0 => 4 + rng.below(4),
            Mix::Uncoloured => 5,
            Mix::NoColours if rng.below(3) == 0 => rng.below(8),
            Mix::NoColours => 2,
            Mix::Coloured if rng.below(3) == 0 => rng.below(4),
            Mix::Coloured => 1,
        };
        let item = &chunks[0].items[id as usize];
        let ci = rng.below(item.cols as u32 - 1);
        let cj = rng.below(item.rows as u32 - 1);
        let a = rng.below(item.nu as u32 + 1);
        let b = rng.below(item.nv as u32 + 1);
        px.set_words(ci << 24 | cj << 16 | a << 8 | b, id | PATCH_SAMPLE);
        expected.push(phong_reference(&r, patches, &frames, id, px.w0()));
    }
    let samples = band.clone();
    let mut rgba = vec![[0u8; 4]; band.len()];
    let mut eye = vec![0f32; band.len()];
    isa.run(|| resolve_band(&r, &band, &mut rgba, &mut eye));
    for (k, (got, want)) in rgba.iter().zip(&expected).enumerate() {
        assert_eq!(got, want, "pixel {k}: {:?}", samples[k]);
    }
    check_box_resolve(&r, &band, width, (&rgba, &eye));
    let covered = samples.iter().filter(|s| s.depth < Z_FAR).count();
    assert!(covered > 300, "{covered}");
    if let Mix::Everything = mix {
        assert!(covered % 4 != 0, "{covered}");
    }
    assert_eq!(eye.iter().filter(|e| e.is_finite()).count(), covered);
    for (e, s) in eye.iter().zip(&samples) {
        if s.depth < Z_FAR {
            assert_eq!(
                *e,
                r.near + s.depth as f32 * ((r.far - r.near) / Z_FAR as f32)
            );
        }
    }
    // How many groups took the fast path: four covered patch samples
    // of items without colours, of one shade frame or of several.
    let fast = |mixed: bool| {
        samples
            .chunks_exact(4)
            .filter(|g| {
                let uncoloured = |s: &Sample| {
                    s.depth < Z_FAR
                        && s.w2() & PATCH_SAMPLE != 0
                        && chunks[0].items[(s.w2() & !PATCH_SAMPLE) as usize].uniform_albedo
                };
                let frame = |s: &Sample| chunks[0].items[(s.w2() & !PATCH_SAMPLE) as usize].frame;
                g.iter().all(uncoloured) && g.iter().any(|s| frame(s) != frame(&g[0])) == mixed
            })
            .count()
    };
    if let Mix::Uncoloured | Mix::NoColours = mix {
        assert!(
            fast(false) > 10 && fast(true) > 10,
            "{} {}",
            fast(false),
            fast(true)
        );
    }
    // How many groups took the coloured path: four covered patch samples
    // of items with colours, of one shade frame or of several.
    let coloured = |mixed: bool| {
        samples
            .chunks_exact(4)
            .filter(|g| {
                let item = |s: &Sample| &chunks[0].items[(s.w2() & !PATCH_SAMPLE) as usize];
                let own = |s: &Sample| {
                    s.depth < Z_FAR && s.w2() & PATCH_SAMPLE != 0 && !item(s).uniform_albedo
                };
                g.iter().all(own) && g.iter().any(|s| item(s).frame != item(&g[0]).frame) == mixed
            })
            .count()
    };
    if let Mix::Coloured = mix {
        assert!(
            coloured(false) > 10 && coloured(true) > 10,
            "{} {}",
            coloured(false),
            coloured(true)
        );
    }
    // Groups of eight covered patch samples (the eight-lane paths).
    let eights = band
        .chunks_exact(8)
        .filter(|g| g.iter().all(|s| s.w2() & PATCH_SAMPLE != 0))
        .count();
    if let Mix::Uncoloured | Mix::Coloured = mix {
        assert!(eights > 10, "{eights}");
    }
}

/// `resolve_box` on `band` (`width` wide, from image row 0) with a box
/// inside it and samples that would panic if read outside the box: the
/// box's pixels are `resolve_band`'s (`whole`), the others background.
fn check_box_resolve(r: &Resolve<'_>, band: &[Sample], width: i32, whole: (&[[u8; 4]], &[f32])) {
    let rows = band.len() as i32 / width;
    let touched = PixelBox {
        x0: 3,
        x1: width - 5,
        y0: 1,
        y1: rows - 1,
    };
    let inside = |k: usize| {
        let (x, y) = (k as i32 % width, k as i32 / width);
        (touched.x0..touched.x1).contains(&x) && (touched.y0..touched.y1).contains(&y)
    };
    let junk = Sample {
        depth: 5,
        w1: u32::MAX,
        words: u64::MAX,
    };
    let px: Vec<Sample> = (0..band.len())
        .map(|k| if inside(k) { band[k] } else { junk })
        .collect();
    let mut rgba = vec![[0u8; 4]; band.len()];
    let mut eye = vec![0f32; band.len()];
    let all_rows = PixelBox::whole(0, rows, width);
    r.isa
        .run(|| resolve_box(r, &px, all_rows, touched, &mut rgba, &mut eye));
    for k in 0..band.len() {
        if inside(k) {
            assert_eq!(
                (rgba[k], eye[k].to_bits()),
                (whole.0[k], whole.1[k].to_bits())
            );
        } else {
            assert_eq!(
                (rgba[k], eye[k]),
                (r.background, f32::INFINITY),
                "pixel {k}"
            );
        }
    }
}
