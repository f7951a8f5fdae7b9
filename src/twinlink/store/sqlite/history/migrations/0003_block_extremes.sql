-- Where the extremes of a block are, so min/max downsampling reads little more than them
-- (store/sqlite/history/sketch.py). Numeric blocks written from now on carry:
--   tmin, tmax: the time of vmin and of vmax (the first of equals);
--   sketch: for blocks of more than 128 samples, per chunk of 128 samples (the last one
--           shorter) six little-endian 8-byte fields: the times of its first and last sample,
--           of its smallest and of its largest value, then those two values (float64).
-- Blocks written before stay NULL there; readers decode them.
ALTER TABLE blocks ADD COLUMN tmin INTEGER;
ALTER TABLE blocks ADD COLUMN tmax INTEGER;
ALTER TABLE blocks ADD COLUMN sketch BLOB;
