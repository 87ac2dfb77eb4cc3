//! A small software splat renderer: every particle is drawn as a shaded sphere impostor (a
//! disc of its own size, lit as a sphere, depth-tested), seen by an orthographic or a
//! perspective camera; 2D scenes are drawn orthographically in the x–y plane. Colours show the
//! body, the plastic strain, the speed or the pressure.

use super::Snapshot;
use std::io::{self, Write};

/// How 3D scenes are projected (2D scenes are always orthographic).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Camera {
    #[default]
    Perspective,
    Orthographic,
}

/// What the colours show.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ColorBy {
    /// One colour per body.
    #[default]
    Body,
    /// Accumulated plastic strain, from 0 to `RenderOptions::scale_max`.
    PlasticStrain,
    /// Speed, from 0 to the frame's largest.
    Speed,
    /// Pressure, from 0 to the frame's largest.
    Pressure,
}

#[derive(Clone, Debug, PartialEq)]
pub struct RenderOptions {
    pub width: u32,
    pub height: u32,
    pub camera: Camera,
    pub color_by: ColorBy,
    /// Camera direction around the vertical axis and above the horizon (degrees, 3D).
    pub azimuth_deg: f64,
    pub elevation_deg: f64,
    /// The plastic strain shown in the top colour.
    pub scale_max: f32,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            width: 800,
            height: 600,
            camera: Camera::Perspective,
            color_by: ColorBy::Body,
            azimuth_deg: 30.0,
            elevation_deg: 25.0,
            scale_max: 0.5,
        }
    }
}

/// An RGB image, rows top to bottom.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<u8>,
}

impl Image {
    fn new(width: u32, height: u32) -> Self {
        let mut rgb = Vec::with_capacity((width * height * 3) as usize);
        for y in 0..height {
            // a soft vertical gradient
            let t = y as f32 / height.max(1) as f32;
            let c = [
                (38.0 + 14.0 * t) as u8,
                (42.0 + 14.0 * t) as u8,
                (50.0 + 14.0 * t) as u8,
            ];
            for _ in 0..width {
                rgb.extend_from_slice(&c);
            }
        }
        Image { width, height, rgb }
    }

    fn put(&mut self, x: i64, y: i64, c: [f32; 3]) {
        if x >= 0 && y >= 0 && (x as u32) < self.width && (y as u32) < self.height {
            let i = ((y as u32 * self.width + x as u32) * 3) as usize;
            for k in 0..3 {
                self.rgb[i + k] = (c[k].clamp(0.0, 1.0) * 255.0 + 0.5) as u8;
            }
        }
    }

    /// Encodes the image as an 8-bit RGB PNG.
    pub fn write_png(&self, out: impl Write) -> io::Result<()> {
        let mut enc = png::Encoder::new(out, self.width, self.height);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        let mut w = enc.write_header().map_err(io::Error::other)?;
        w.write_image_data(&self.rgb).map_err(io::Error::other)?;
        w.finish().map_err(io::Error::other)
    }
}

/// Projects world points to pixels.
struct View {
    dim: usize,
    perspective: bool,
    eye: [f64; 3],
    right: [f64; 3],
    up: [f64; 3],
    forward: [f64; 3],
    /// Pixels per unit of view-plane length at depth 1 (perspective) or per metre (ortho).
    focal: f64,
    cx: f64,
    cy: f64,
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn normalize(a: [f64; 3]) -> [f64; 3] {
    let l = dot(a, a).sqrt();
    a.map(|x| x / l)
}
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

impl View {
    fn new(s: &Snapshot, o: &RenderOptions) -> Self {
        let (w, h) = (o.width as f64, o.height as f64);
        let d = s.domain;
        if s.dim == 2 {
            let margin = 0.04 * w.min(h);
            let k = ((w - 2.0 * margin) / d[0].max(1e-9)).min((h - 2.0 * margin) / d[1].max(1e-9));
            return View {
                dim: 2,
                perspective: false,
                eye: [0.5 * d[0], 0.5 * d[1], -1.0],
                right: [1.0, 0.0, 0.0],
                up: [0.0, 1.0, 0.0],
                forward: [0.0, 0.0, 1.0],
                focal: k,
                cx: 0.5 * w,
                cy: 0.5 * h,
            };
        }
        let target = [0.5 * d[0], 0.4 * d[1], 0.5 * d[2]];
        let radius = 0.5 * dot(d, d).sqrt();
        let (az, el) = (o.azimuth_deg.to_radians(), o.elevation_deg.to_radians());
        let dir = [az.sin() * el.cos(), el.sin(), az.cos() * el.cos()];
        let forward = dir.map(|x| -x);
        let right = normalize(cross(forward, [0.0, 1.0, 0.0]));
        let up = cross(right, forward);
        let half_fov: f64 = 20f64.to_radians();
        let fit = 0.5 * w.min(h) * 0.98;
        if o.camera == Camera::Perspective {
            let dist = radius / half_fov.sin();
            View {
                dim: 3,
                perspective: true,
                eye: std::array::from_fn(|a| target[a] + dir[a] * dist),
                right,
                up,
                forward,
                focal: fit / half_fov.tan(),
                cx: 0.5 * w,
                cy: 0.5 * h,
            }
        } else {
            View {
                dim: 3,
                perspective: false,
                eye: std::array::from_fn(|a| target[a] + dir[a] * 4.0 * radius),
                right,
                up,
                forward,
                focal: fit / radius,
                cx: 0.5 * w,
                cy: 0.5 * h,
            }
        }
    }

    /// Pixel coordinates, depth and pixels per metre at that depth.
    fn project(&self, p: [f64; 3]) -> Option<(f64, f64, f64, f64)> {
        let e = std::array::from_fn(|a| p[a] - self.eye[a]);
        let (x, y, z) = (dot(e, self.right), dot(e, self.up), dot(e, self.forward));
        if self.perspective {
            if z <= 1e-6 {
                return None;
            }
            let k = self.focal / z;
            Some((self.cx + x * k, self.cy - y * k, z, k))
        } else {
            let k = self.focal;
            let (x, y) = if self.dim == 2 {
                (p[0] - self.eye[0], p[1] - self.eye[1])
            } else {
                (x, y)
            };
            Some((self.cx + x * k, self.cy - y * k, z, k))
        }
    }
}

const PALETTE: [[f32; 3]; 8] = [
    [0.91, 0.55, 0.25],
    [0.30, 0.60, 0.85],
    [0.45, 0.75, 0.40],
    [0.85, 0.35, 0.40],
    [0.65, 0.50, 0.80],
    [0.90, 0.80, 0.35],
    [0.40, 0.75, 0.75],
    [0.75, 0.60, 0.50],
];

/// A blue–cyan–green–yellow–red ramp for t in [0, 1].
pub fn ramp(t: f32) -> [f32; 3] {
    const STOPS: [[f32; 3]; 5] = [
        [0.20, 0.30, 0.75],
        [0.20, 0.70, 0.85],
        [0.35, 0.80, 0.35],
        [0.95, 0.85, 0.25],
        [0.85, 0.25, 0.20],
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        1.0
    } * 4.0;
    let i = (t.floor() as usize).min(3);
    let f = t - i as f32;
    std::array::from_fn(|k| STOPS[i][k] * (1.0 - f) + STOPS[i + 1][k] * f)
}

/// Renders the particles.
pub fn render(s: &Snapshot, o: &RenderOptions) -> Image {
    let mut img = Image::new(o.width.max(1), o.height.max(1));
    let view = View::new(s, o);
    draw_domain(&mut img, &view, s);
    let n = s.len();
    let colour_scale = match o.color_by {
        ColorBy::Body => 1.0,
        ColorBy::PlasticStrain => o.scale_max.max(1e-6),
        ColorBy::Speed => s
            .velocity
            .iter()
            .map(|v| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt())
            .filter(|x| x.is_finite())
            .fold(1e-6, f32::max),
        ColorBy::Pressure => s
            .pressure
            .iter()
            .copied()
            .filter(|x| x.is_finite())
            .fold(1e-6, f32::max),
    };
    let (w, h) = (img.width as usize, img.height as usize);
    let mut depth = vec![f32::INFINITY; w * h];
    // light from the upper left, in front
    let light = normalize([-0.45, 0.65, -0.6]);
    for i in 0..n {
        let p = s.position[i].map(|x| x as f64);
        if !p.iter().all(|x| x.is_finite()) {
            continue;
        }
        let Some((px, py, z, k)) = view.project(p) else {
            continue;
        };
        let r_world = 0.5 * (s.volume[i].max(0.0) as f64).powf(1.0 / s.dim as f64);
        let r = (r_world * k * 1.15).max(0.7);
        let base = match o.color_by {
            ColorBy::Body => PALETTE[s.body[i] as usize % PALETTE.len()],
            ColorBy::PlasticStrain => ramp(s.plastic_strain[i] / colour_scale),
            ColorBy::Speed => {
                let v = s.velocity[i];
                ramp((v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt() / colour_scale)
            }
            ColorBy::Pressure => ramp(s.pressure[i] / colour_scale),
        };
        let (x0, x1) = ((px - r).floor() as i64, (px + r).ceil() as i64);
        let (y0, y1) = ((py - r).floor() as i64, (py + r).ceil() as i64);
        if x1 < 0 || y1 < 0 || x0 >= w as i64 || y0 >= h as i64 {
            continue;
        }
        for y in y0.max(0)..=y1.min(h as i64 - 1) {
            for x in x0.max(0)..=x1.min(w as i64 - 1) {
                let u = (x as f64 + 0.5 - px) / r;
                let v = (py - (y as f64 + 0.5)) / r;
                let q = u * u + v * v;
                if q > 1.0 {
                    continue;
                }
                let nz = (1.0 - q).sqrt();
                let d = (z - nz * r_world) as f32;
                let slot = y as usize * w + x as usize;
                if d >= depth[slot] {
                    continue;
                }
                depth[slot] = d;
                let normal = [u, v, -nz];
                let diffuse = dot(normal, light).max(0.0);
                let half = normalize([light[0], light[1], light[2] - 1.0]);
                let spec = dot(normal, half).max(0.0).powi(24) * 0.25;
                let shade = (0.32 + 0.68 * diffuse) as f32;
                let c = base.map(|c| c * shade + spec as f32);
                img.put(x, y, c);
            }
        }
    }
    img
}

/// The domain's outline (2D) or its floor and edges (3D).
fn draw_domain(img: &mut Image, view: &View, s: &Snapshot) {
    let d = s.domain;
    let c = [0.55, 0.57, 0.62];
    if s.dim == 2 {
        let corners = [[0.0, 0.0], [d[0], 0.0], [d[0], d[1]], [0.0, d[1]]];
        for i in 0..4 {
            let (a, b) = (corners[i], corners[(i + 1) % 4]);
            line(img, view, [a[0], a[1], 0.0], [b[0], b[1], 0.0], c);
        }
        return;
    }
    // the floor, filled
    let floor = [
        [0.0, 0.0, 0.0],
        [d[0], 0.0, 0.0],
        [d[0], 0.0, d[2]],
        [0.0, 0.0, d[2]],
    ];
    let projected: Vec<Option<(f64, f64)>> = floor
        .iter()
        .map(|&p| view.project(p).map(|(x, y, _, _)| (x, y)))
        .collect();
    if let [Some(a), Some(b), Some(cc), Some(dd)] = projected[..] {
        fill_triangle(img, a, b, cc, [0.30, 0.31, 0.34]);
        fill_triangle(img, a, cc, dd, [0.30, 0.31, 0.34]);
    }
    let e = |m: usize| -> [f64; 3] {
        std::array::from_fn(|a| if m >> a & 1 == 1 { d[a] } else { 0.0 })
    };
    for m in 0..8usize {
        for a in 0..3 {
            if m >> a & 1 == 0 {
                line(img, view, e(m), e(m | 1 << a), c);
            }
        }
    }
}

fn line(img: &mut Image, view: &View, a: [f64; 3], b: [f64; 3], c: [f32; 3]) {
    let (Some(pa), Some(pb)) = (view.project(a), view.project(b)) else {
        return;
    };
    let steps = (pb.0 - pa.0).abs().max((pb.1 - pa.1).abs()).ceil().min(1e5) as i64;
    for k in 0..=steps {
        let t = if steps == 0 {
            0.0
        } else {
            k as f64 / steps as f64
        };
        img.put(
            (pa.0 + t * (pb.0 - pa.0)).floor() as i64,
            (pa.1 + t * (pb.1 - pa.1)).floor() as i64,
            c,
        );
    }
}

fn fill_triangle(img: &mut Image, a: (f64, f64), b: (f64, f64), c: (f64, f64), col: [f32; 3]) {
    let edge = |p: (f64, f64), q: (f64, f64), x: f64, y: f64| {
        (q.0 - p.0) * (y - p.1) - (q.1 - p.1) * (x - p.0)
    };
    let area = edge(a, b, c.0, c.1);
    if area.abs() < 1e-12 {
        return;
    }
    let x0 = a.0.min(b.0).min(c.0).floor().max(0.0) as i64;
    let x1 = a.0.max(b.0).max(c.0).ceil().min(img.width as f64 - 1.0) as i64;
    let y0 = a.1.min(b.1).min(c.1).floor().max(0.0) as i64;
    let y1 = a.1.max(b.1).max(c.1).ceil().min(img.height as f64 - 1.0) as i64;
    for y in y0..=y1 {
        for x in x0..=x1 {
            let (px, py) = (x as f64 + 0.5, y as f64 + 0.5);
            let (w0, w1, w2) = (edge(b, c, px, py), edge(c, a, px, py), edge(a, b, px, py));
            if (w0 >= 0.0 && w1 >= 0.0 && w2 >= 0.0) || (w0 <= 0.0 && w1 <= 0.0 && w2 <= 0.0) {
                img.put(x, y, col);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn snapshot(dim: usize) -> Snapshot {
        Snapshot {
            dim,
            domain: if dim == 2 {
                [1.0, 1.0, 0.0]
            } else {
                [1.0, 1.0, 1.0]
            },
            // (the 3D camera looks at 40 % of the domain height)
            position: vec![if dim == 2 {
                [0.5, 0.5, 0.0]
            } else {
                [0.5, 0.4, 0.5]
            }],
            velocity: vec![[0.0; 3]],
            body: vec![0],
            plastic_strain: vec![0.0],
            pressure: vec![0.0],
            volume: vec![if dim == 2 { 0.01 } else { 0.001 }],
            ..Default::default()
        }
    }

    #[test]
    fn a_particle_is_drawn_in_the_middle() {
        for dim in [2, 3] {
            for camera in [Camera::Perspective, Camera::Orthographic] {
                let o = RenderOptions {
                    width: 64,
                    height: 48,
                    camera,
                    ..Default::default()
                };
                let img = render(&snapshot(dim), &o);
                assert_eq!(img.rgb.len(), 64 * 48 * 3);
                let centre = ((24 * 64 + 32) * 3) as usize;
                let px = &img.rgb[centre..centre + 3];
                // the body colour is orange: red well above blue
                assert!(
                    px[0] as i32 - px[2] as i32 > 40,
                    "{dim}D {camera:?}: {px:?}"
                );
                let corner = &img.rgb[0..3];
                assert!((corner[0] as i32 - corner[2] as i32).abs() < 20);
            }
        }
    }

    #[test]
    fn png_round_trip() {
        let img = render(&snapshot(2), &RenderOptions::default());
        let mut bytes = Vec::new();
        img.write_png(&mut bytes).unwrap();
        let dec = png::Decoder::new(std::io::Cursor::new(bytes));
        let mut reader = dec.read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut buf).unwrap();
        assert_eq!((info.width, info.height), (800, 600));
        assert_eq!(&buf[..info.buffer_size()], &img.rgb[..]);
    }
}
