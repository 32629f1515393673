//! A sharded collection's episodes as the driver sees them: what each worker reports, and the
//! raw episode files HDF5-bound workers write (`<staging>/shards/<i>.episode`) and the driver
//! reads back to append with the one HDF5 writer.

use std::fs;
use std::path::Path;

use crate::episode::{EpisodeRecord, InfoColumn};
use crate::error::DatasetError;
use crate::layout::SHARDS_DIR;

/// What a worker reports of each episode it recorded: all the driver needs to merge.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ShardEpisode {
    /// Steps the episode took.
    pub steps: u64,
    /// Bytes of its Arrow files (`dataset_size` is their sum); 0 for HDF5, where the driver
    /// measures the one file it writes.
    pub bytes: u64,
}

/// An episode read back from a shard file.
pub(crate) struct OwnedEpisode {
    pub seed: Option<u64>,
    pub observations: Vec<f64>,
    pub actions: Vec<f32>,
    pub rewards: Vec<f64>,
    pub terminations: Vec<bool>,
    pub truncations: Vec<bool>,
    pub infos: Vec<InfoColumn>,
}

impl OwnedEpisode {
    pub(crate) fn record(&self) -> EpisodeRecord<'_> {
        EpisodeRecord {
            seed: self.seed,
            observations: &self.observations,
            actions: &self.actions,
            rewards: &self.rewards,
            terminations: &self.terminations,
            truncations: &self.truncations,
            infos: &self.infos,
        }
    }
}

const MAGIC: &[u8; 8] = b"envcep01";

/// Little-endian: magic, seed (u64::MAX + flag), then each array as a u64 length and its values;
/// infos as a count, then key, width and values each.
pub(crate) fn encode(ep: &EpisodeRecord<'_>) -> Vec<u8> {
    let mut b = Vec::with_capacity(8 * (ep.observations.len() + 4 * ep.rewards.len()) + 64);
    b.extend_from_slice(MAGIC);
    b.push(u8::from(ep.seed.is_some()));
    b.extend_from_slice(&ep.seed.unwrap_or(0).to_le_bytes());
    let len = |b: &mut Vec<u8>, n: usize| b.extend_from_slice(&(n as u64).to_le_bytes());
    len(&mut b, ep.observations.len());
    ep.observations
        .iter()
        .for_each(|x| b.extend_from_slice(&x.to_le_bytes()));
    len(&mut b, ep.actions.len());
    ep.actions
        .iter()
        .for_each(|x| b.extend_from_slice(&x.to_le_bytes()));
    len(&mut b, ep.rewards.len());
    ep.rewards
        .iter()
        .for_each(|x| b.extend_from_slice(&x.to_le_bytes()));
    for flags in [ep.terminations, ep.truncations] {
        len(&mut b, flags.len());
        b.extend(flags.iter().map(|&f| u8::from(f)));
    }
    len(&mut b, ep.infos.len());
    for c in ep.infos {
        len(&mut b, c.key.len());
        b.extend_from_slice(c.key.as_bytes());
        len(&mut b, c.width);
        len(&mut b, c.values.len());
        c.values
            .iter()
            .for_each(|x| b.extend_from_slice(&x.to_le_bytes()));
    }
    b
}

struct Cursor<'a> {
    b: &'a [u8],
    at: usize,
}

impl Cursor<'_> {
    fn take(&mut self, n: usize) -> Option<&[u8]> {
        let s = self.b.get(self.at..self.at.checked_add(n)?)?;
        self.at += n;
        Some(s)
    }
    fn u64(&mut self) -> Option<u64> {
        Some(u64::from_le_bytes(self.take(8)?.try_into().ok()?))
    }
    fn len(&mut self) -> Option<usize> {
        let n = usize::try_from(self.u64()?).ok()?;
        // Never allocate more than the file could hold.
        (n <= self.b.len()).then_some(n)
    }
    fn f64s(&mut self) -> Option<Vec<f64>> {
        let n = self.len()?;
        let raw = self.take(n.checked_mul(8)?)?;
        Some(
            raw.chunks_exact(8)
                .map(|c| f64::from_le_bytes(c.try_into().unwrap_or([0; 8])))
                .collect(),
        )
    }
}

/// Read a shard episode file; `None` for a truncated or foreign file.
fn decode(b: &[u8]) -> Option<OwnedEpisode> {
    let mut c = Cursor { b, at: 0 };
    if c.take(8)? != MAGIC {
        return None;
    }
    let has_seed = c.take(1)?[0] == 1;
    let seed = c.u64()?;
    let observations = c.f64s()?;
    let n = c.len()?;
    let actions = c
        .take(n.checked_mul(4)?)?
        .chunks_exact(4)
        .map(|x| f32::from_le_bytes(x.try_into().unwrap_or([0; 4])))
        .collect();
    let rewards = c.f64s()?;
    let mut flags = || -> Option<Vec<bool>> {
        let n = c.len()?;
        Some(c.take(n)?.iter().map(|&x| x == 1).collect())
    };
    let terminations = flags()?;
    let truncations = flags()?;
    let n = c.len()?;
    let mut infos = Vec::with_capacity(n.min(64));
    for _ in 0..n {
        let k = c.len()?;
        let key = String::from_utf8(c.take(k)?.to_vec()).ok()?;
        let width = c.len()?;
        let values = c.f64s()?;
        infos.push(InfoColumn { key, width, values });
    }
    (c.at == b.len()).then_some(OwnedEpisode {
        seed: has_seed.then_some(seed),
        observations,
        actions,
        rewards,
        terminations,
        truncations,
        infos,
    })
}

/// Read shard episode `index` from `staging` (E1600 when missing or damaged).
pub(crate) fn read_shard_episode(staging: &Path, index: u64) -> Result<OwnedEpisode, DatasetError> {
    let path = staging.join(SHARDS_DIR).join(format!("{index}.episode"));
    let missing = |why: String| DatasetError::ShardMissing {
        path: path.clone(),
        index,
        why,
    };
    let bytes = fs::read(&path).map_err(|e| missing(e.to_string()))?;
    decode(&bytes).ok_or_else(|| missing("truncated or not an envc shard episode".into()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shard_episodes_round_trip_and_damage_is_refused() {
        let infos = vec![InfoColumn {
            key: "x_position".into(),
            width: 1,
            values: vec![0.5, -1.25, 3.0],
        }];
        let rec = EpisodeRecord {
            seed: Some(42),
            observations: &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0],
            actions: &[0.25, -0.5],
            rewards: &[1.5, f64::MIN_POSITIVE],
            terminations: &[false, true],
            truncations: &[false, false],
            infos: &infos,
        };
        let bytes = encode(&rec);
        let back = decode(&bytes).unwrap();
        assert_eq!(back.seed, Some(42));
        assert_eq!(back.observations, rec.observations);
        assert_eq!(back.actions, rec.actions);
        assert_eq!(back.rewards, rec.rewards);
        assert_eq!(back.terminations, rec.terminations);
        assert_eq!(back.truncations, rec.truncations);
        assert_eq!(back.infos[0].key, "x_position");
        assert_eq!(back.infos[0].values, infos[0].values);
        for cut in [0, 7, 9, 30, bytes.len() - 1] {
            assert!(decode(&bytes[..cut]).is_none(), "cut at {cut}");
        }
    }
}
