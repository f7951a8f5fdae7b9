-- Whether a stored batch also reached the bus (docs/decisions/0013): a device batch is
-- acknowledged once it is committed here AND published, so one committed whose publish
-- failed (Kafka down) is answered 503 and sent again; the resend finds it stored and must
-- publish it then, or live views and processors never see it. New rows start false and the
-- node marks them once the bus has them; rows from before this column were published.
ALTER TABLE ingested ADD COLUMN published boolean NOT NULL DEFAULT true;
