-- Which times a block holds, as a number: the sum (mod 2^62) of a 64-bit mix of each of its
-- times (store/sqlite/history/codec.py `times_hash`). The sum of a signal's blocks stands for
-- the multiset of its times, so /streams can tell that signals were sent together (equal
-- sums) and count a stream's samples (rows joined on time) without reading its blocks.
-- Blocks written before stay NULL; readers read their times instead.
ALTER TABLE blocks ADD COLUMN times_hash INTEGER;
