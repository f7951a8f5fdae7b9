"""Exchange formats for DT documents (docs/formats.md): W3C WoT Thing Description 1.1,
DTDL v3 and the Asset Administration Shell, exported from and imported into a document."""
