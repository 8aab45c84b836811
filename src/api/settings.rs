//! Render settings by name: the command line's flags (or the field names) with the ranges of
//! the one table, [`crate::settings::SETTINGS`].

use crate::error::{Error, Result};
use crate::settings::{
    setting, Filter, FresnelMode, Mode, RenderSettings, Sampler, Slot, SETTINGS,
};

/// A value for [`RenderSettings::set`].
#[derive(Clone, Debug, PartialEq)]
pub enum SettingValue {
    /// An integer (any numeric setting).
    Int(i64),
    /// A number (a real-valued setting; an integral one for an integer setting).
    Float(f64),
    /// A name (`mode`, `filter`, `sampler`, `fresnel`).
    Text(String),
}

impl From<i64> for SettingValue {
    fn from(v: i64) -> Self {
        SettingValue::Int(v)
    }
}
impl From<u32> for SettingValue {
    fn from(v: u32) -> Self {
        SettingValue::Int(v.into())
    }
}
impl From<f64> for SettingValue {
    fn from(v: f64) -> Self {
        SettingValue::Float(v)
    }
}
impl From<f32> for SettingValue {
    fn from(v: f32) -> Self {
        SettingValue::Float(v.into())
    }
}
impl From<&str> for SettingValue {
    fn from(v: &str) -> Self {
        SettingValue::Text(v.to_string())
    }
}

/// The named choices and what they accept.
const CHOICES: [(&str, &[&str]); 4] = [
    ("mode", &Mode::NAMES),
    ("filter", &Filter::NAMES),
    ("sampler", &Sampler::NAMES),
    ("fresnel", &["exact", "schlick"]),
];

impl RenderSettings {
    /// The names [`RenderSettings::set`] accepts (the command line's flags; the field names
    /// with `_` work too).
    pub fn names() -> Vec<&'static str> {
        let numbers = SETTINGS.iter().map(|s| s.flag);
        numbers.chain(CHOICES.iter().map(|c| c.0)).collect()
    }

    /// Sets the setting `name` (a flag such as `caustic-photons`, or the field
    /// `caustic_photons`) to `value`, refusing a value outside its range with
    /// [`Error::Setting`], exactly as the command line does.
    pub fn set(&mut self, name: &str, value: impl Into<SettingValue>) -> Result<()> {
        let value = value.into();
        let key = name.replace('_', "-");
        if let Some(&(field, names)) = CHOICES.iter().find(|c| c.0 == key) {
            return self.set_choice(field, names, &value);
        }
        let Some(row) = SETTINGS.iter().find(|s| s.flag == key) else {
            return Err(Error::Setting {
                field: "name",
                message: format!(
                    "unknown setting '{name}' (known: {})",
                    Self::names().join(", ")
                ),
            });
        };
        let refuse = |message: String| Error::Setting {
            field: row.flag,
            message,
        };
        let mut next = self.clone();
        match (row.slot, &value) {
            (Slot::U32 { set, .. }, SettingValue::Int(v)) => {
                let v = u32::try_from(*v).map_err(|_| refuse(row.range.refusal(v)))?;
                set(&mut next, v);
            }
            (Slot::U32 { set, .. }, SettingValue::Float(v)) if v.fract() == 0.0 => {
                if !(0.0..=u32::MAX as f64).contains(v) {
                    return Err(refuse(row.range.refusal(v)));
                }
                set(&mut next, *v as u32);
            }
            (Slot::F32 { set, .. }, SettingValue::Int(v)) => set(&mut next, *v as f32),
            (Slot::F32 { set, .. }, SettingValue::Float(v)) => set(&mut next, *v as f32),
            (_, v) => {
                return Err(refuse(format!(
                    "{v:?}: expected {}",
                    row.range.requirement()
                )))
            }
        }
        row.check(&next)?;
        *self = next;
        Ok(())
    }

    /// The value of the numeric setting `name` (a flag or a field), `None` for an unknown
    /// name or an unset optional one.
    pub fn get(&self, name: &str) -> Option<f64> {
        match setting(&name.replace('-', "_"))?.slot {
            Slot::U32 { get, .. } => Some(get(self).into()),
            Slot::F32 { get, .. } => get(self).map(f64::from),
        }
    }

    fn set_choice(
        &mut self,
        field: &'static str,
        names: &[&str],
        value: &SettingValue,
    ) -> Result<()> {
        let refuse = |shown: String| Error::Setting {
            field,
            message: format!("{shown}: expected one of {}", names.join(", ")),
        };
        let SettingValue::Text(text) = value else {
            return Err(refuse(format!("{value:?}")));
        };
        match field {
            "mode" => self.mode = Mode::parse(text).ok_or_else(|| refuse(text.clone()))?,
            "filter" => self.filter = Filter::parse(text).ok_or_else(|| refuse(text.clone()))?,
            "sampler" => self.sampler = Sampler::parse(text).ok_or_else(|| refuse(text.clone()))?,
            _ => {
                self.fresnel = match text.as_str() {
                    "exact" => FresnelMode::Exact,
                    "schlick" => FresnelMode::Schlick,
                    _ => return Err(refuse(text.clone())),
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn set_by_flag_or_field_with_the_table_ranges() {
        let mut s = RenderSettings::default();
        s.set("caustic-photons", 5u32).unwrap();
        s.set("caustic_photons", 7i64).unwrap();
        s.set("alpha", 0.5).unwrap();
        s.set("mode", "direct").unwrap();
        assert_eq!((s.caustic_photons, s.alpha, s.mode), (7, 0.5, Mode::Direct));
        assert_eq!(s.get("caustic-photons"), Some(7.0));
        let e = s.set("spp", 0i64).unwrap_err().to_string();
        assert_eq!(e, "invalid setting spp: 0 is outside 1..=65536");
        let e = s.set("spp", -3i64).unwrap_err().to_string();
        assert_eq!(e, "invalid setting spp: -3 is outside 1..=65536");
        let e = s.set("alpha", 1.5).unwrap_err().to_string();
        assert_eq!(e, "invalid setting alpha: 1.5 is outside (0, 1)");
        let e = s.set("mode", "fast").unwrap_err().to_string();
        assert!(e.starts_with("invalid setting mode: fast: expected one of photon, direct"));
        assert!(s.set("colour", 1i64).is_err());
        assert_eq!(
            s.spp,
            RenderSettings::default().spp,
            "a refusal changes nothing"
        );
    }
}
