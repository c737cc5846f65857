//! Periodic records on their way to the spectra: the first periods left out
//! ([`Identifier::drop_periods`](super::Identifier::drop_periods)) and the checks against the
//! stated period ([`PeriodCheck`]).

use std::borrow::Cow;

use crate::error::{Result, Warning};
use crate::records::Record;
use crate::screening::PeriodCheck;
use crate::spectra::Segmentation;

use super::Settings;

impl Settings {
    /// `record` without its first [`Settings::drop_periods`] periods (as it is for other
    /// segmentations or none dropped).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) (`trim range end`) when the
    /// periods dropped are the whole record.
    pub(super) fn steady(&self, record: Record) -> Result<Record> {
        match self.segmentation {
            Segmentation::Periods { len } if self.drop_periods > 0 => {
                record.trimmed((self.drop_periods * len).min(record.len() + 1)..record.len())
            }
            _ => Ok(record),
        }
    }

    /// [`Settings::steady`] of every record, borrowed when nothing is dropped.
    pub(super) fn steady_all<'a>(&self, records: &'a [Record]) -> Result<Cow<'a, [Record]>> {
        match self.segmentation {
            Segmentation::Periods { .. } if self.drop_periods > 0 => Ok(Cow::Owned(
                records
                    .iter()
                    .map(|r| self.steady(r.clone()))
                    .collect::<Result<_>>()?,
            )),
            _ => Ok(Cow::Borrowed(records)),
        }
    }

    /// The period checks, for periodic records.
    pub(super) fn period_check(&self) -> Option<PeriodCheck> {
        match self.segmentation {
            Segmentation::Periods { len } => Some(PeriodCheck::new(len)),
            _ => None,
        }
    }

    /// The period checks' warnings on `records` (none unless periodic).
    pub(super) fn period_warnings(&self, records: &[Record]) -> Vec<Warning> {
        let Some(mut check) = self.period_check() else {
            return Vec::new();
        };
        records.iter().for_each(|r| check.record(r));
        check.warnings()
    }
}
