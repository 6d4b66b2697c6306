use spatch_earth::{
    heights_from_colour, heights_from_elevation, ColourMap, ElevationOptions, HueLevels,
};

#[test]
fn the_built_in_map_gives_sea_and_land() {
    let map = ColourMap::built_in().unwrap();
    assert_eq!((map.width(), map.height()), (1024, 512));
    let heights = heights_from_colour(&map, &HueLevels::default());
    let values = heights.values();
    let sea = values.iter().filter(|&&h| h < 0.05).count() as f64 / values.len() as f64;
    // About 71 % of the Earth is water, but the equirectangular map stretches
    // the white polar ice (Antarctica, the Arctic pack) over a quarter of its
    // pixels: measured 54 % water, 23 % ice, 22 % other land before smoothing.
    assert!((0.4..0.7).contains(&sea), "sea share {sea}");
    assert!((heights.sample(0.0, -85.0) - HueLevels::default().ice_height).abs() < 0.05);
    let (_, max) = heights.range();
    assert!(max > 0.5, "no relief: max {max}");
    // The middle of the Pacific is sea, the Sahara is land.
    assert!(heights.sample(-150.0, 0.0) < 0.05);
    assert!(heights.sample(10.0, 23.0) > 0.4);
}

#[test]
fn the_shared_map_halves_to_the_original_size() {
    let Some(path) = spatch_fixtures::shared_data("earth/earth_nasa_2048x1024.jpg") else {
        return;
    };
    let map = ColourMap::load(&path, 1024).unwrap();
    assert_eq!((map.width(), map.height()), (1024, 512));
}

#[test]
fn the_shared_relief_map_has_land_and_sea_floor() {
    let Some(path) = spatch_fixtures::shared_data("earth/earth_relief8_1350x675.png") else {
        return;
    };
    // This shaded relief puts the coastline at about 92 (the Netherlands 95,
    // Bangladesh 100, the North Sea shelf 82, the open Pacific 34).
    let mut options = ElevationOptions::default();
    options.sea_level = 92.0;
    let heights = heights_from_elevation(&path, &options).unwrap();
    assert_eq!((heights.width(), heights.height()), (1350, 675));
    let (lo, hi) = heights.range();
    assert!(lo < -0.5 && hi > 0.5, "relief range {lo}..{hi}");
    assert!(heights.sample(88.0, 32.0) > 0.5, "Tibet");
    assert!(heights.sample(-150.0, 0.0) < -0.3, "Pacific floor");
    assert!(
        heights.sample(142.0, 11.0) < heights.sample(-30.0, -30.0),
        "Mariana deeper than the mid-Atlantic"
    );
}

#[test]
fn a_colour_image_is_refused_as_elevation() {
    let Some(path) = spatch_fixtures::shared_data("earth/earth_nasa_2048x1024.jpg") else {
        return;
    };
    let err = heights_from_elevation(&path, &ElevationOptions::default()).unwrap_err();
    assert!(err.to_string().contains("greyscale"), "{err}");
}
