//! Particle frames as binary little-endian PLY (readable by ParaView, Blender, MeshLab,
//! CloudCompare): one `vertex` element per particle with `x y z`, `vx vy vz` (float),
//! `body` (int), `plastic_strain` and `pressure` (float). In 2D, z and vz are zero.

use super::Snapshot;
use std::io::{self, Write};

/// Bytes of one particle record.
pub const RECORD_BYTES: usize = 6 * 4 + 4 + 2 * 4;

/// The PLY header for `n` particles.
pub fn header(n: usize, comment: &str) -> String {
    let comment: String = comment
        .chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect();
    format!(
        "ply\nformat binary_little_endian 1.0\ncomment {comment}\nelement vertex {n}\n\
         property float x\nproperty float y\nproperty float z\n\
         property float vx\nproperty float vy\nproperty float vz\n\
         property int body\nproperty float plastic_strain\nproperty float pressure\n\
         end_header\n"
    )
}

/// Writes the snapshot as a binary PLY file.
pub fn write(out: &mut impl Write, s: &Snapshot) -> io::Result<()> {
    let comment = format!("mpm dim {} time {}", s.dim, s.time);
    out.write_all(header(s.len(), &comment).as_bytes())?;
    let mut buf = Vec::with_capacity(s.len() * RECORD_BYTES);
    for i in 0..s.len() {
        for x in s.position[i].iter().chain(&s.velocity[i]) {
            buf.extend_from_slice(&x.to_le_bytes());
        }
        buf.extend_from_slice(&(s.body[i] as i32).to_le_bytes());
        buf.extend_from_slice(&s.plastic_strain[i].to_le_bytes());
        buf.extend_from_slice(&s.pressure[i].to_le_bytes());
    }
    out.write_all(&buf)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn records_follow_the_header() {
        let s = Snapshot {
            dim: 2,
            position: vec![[1.0, 2.0, 0.0]; 3],
            velocity: vec![[0.5, -1.0, 0.0]; 3],
            body: vec![0, 1, 1],
            plastic_strain: vec![0.0, 0.1, 0.2],
            pressure: vec![10.0; 3],
            volume: vec![1e-4; 3],
            ..Default::default()
        };
        let mut bytes = Vec::new();
        write(&mut bytes, &s).unwrap();
        let h = header(3, "mpm dim 2 time 0");
        assert_eq!(bytes.len(), h.len() + 3 * RECORD_BYTES);
        let rec = &bytes[h.len() + RECORD_BYTES..];
        assert_eq!(f32::from_le_bytes(rec[4..8].try_into().unwrap()), 2.0);
        assert_eq!(i32::from_le_bytes(rec[24..28].try_into().unwrap()), 1);
        assert_eq!(f32::from_le_bytes(rec[28..32].try_into().unwrap()), 0.1);
    }
}
