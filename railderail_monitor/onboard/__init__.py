"""The on-board monitor's library: criteria on measured signals only (`criteria`) and an estimator of the
hidden safety quantities from them (`estimator`); docs/onboard-criteria.md."""
