"""Deterministic, realistic-looking DT documents for benchmarks.

Every twin is a machine or a site (a hall, plant or line) with 3-8 features in the style of the
Ilmatar example: what each data system holds, where it is and how to get access, with keywords
drawn from a vocabulary of a few hundred words (Zipf-like, so some words are common and most
are rare, as in real catalogues). About a quarter of the twins also have a group part and a
tenth a private part; most machines name a site as their parent.

The same seed always gives the same documents, byte for byte. The words and tables they are
made of are in `_vocabulary.py`.
"""

from __future__ import annotations

import itertools
import random
import re
import unicodedata
from dataclasses import dataclass, field
from typing import Any

import yaml

from _vocabulary import (
    EQUIPMENT,
    FEATURES,
    FIXED_QUERIES,
    GROUP_FEATURES,
    MANUFACTURERS,
    OWNERS,
    REQUIREMENTS,
    RETENTIONS,
    SITE_KINDS,
    SITES,
    VOCABULARY,
)


def _zipf_weights(n: int, s: float = 0.8) -> list[float]:
    return [1.0 / (rank**s) for rank in range(1, n + 1)]


@dataclass
class GeneratedTwin:
    key: str  # the document id, stable across runs
    public: dict[str, Any]
    extra_parts: list[dict[str, Any]] = field(default_factory=list)
    slug: str = ""  # filled in from the server's answer

    def documents(self) -> list[dict[str, Any]]:
        return [self.public, *self.extra_parts]


_Dumper = getattr(yaml, "CSafeDumper", yaml.SafeDumper)


def dump(doc: dict[str, Any]) -> str:
    return yaml.dump(doc, Dumper=_Dumper, sort_keys=False, allow_unicode=True, width=100)


def dump_stream(docs: list[dict[str, Any]]) -> bytes:
    return "".join("---\n" + dump(d) for d in docs).encode("utf-8")


class Generator:
    def __init__(self, seed: int = 42) -> None:
        self.rng = random.Random(seed)
        # Shuffle once so that which words are common is seeded too, not alphabetical.
        words = list(VOCABULARY)
        self.rng.shuffle(words)
        self.words = words
        self.cum_weights = list(itertools.accumulate(_zipf_weights(len(words))))

    def words_(self, k: int) -> list[str]:
        out: list[str] = []
        while len(out) < k:
            w = self.rng.choices(self.words, cum_weights=self.cum_weights)[0]
            if w not in out:
                out.append(w)
        return out

    def _feature(
        self, template: tuple[str, str, list[str]], eq: str, base_kw: list[str]
    ) -> dict[str, Any]:
        rng = self.rng
        name, text, own_kw = template
        a, b, c = self.words_(3)
        description = text.format(
            eq=eq, a=a, b=b, c=c, n=rng.choice([1, 5, 10, 30, 60]), year=rng.randint(1995, 2025)
        )
        n_kw = rng.randint(3, 8)
        keywords = list(
            dict.fromkeys(
                rng.sample(own_kw, min(len(own_kw), rng.randint(1, 3)))
                + rng.sample(base_kw, min(len(base_kw), rng.randint(0, 2)))
                + self.words_(n_kw)
            )
        )[:n_kw]
        port = rng.randint(8000, 8999)
        feature: dict[str, Any] = {"name": name, "description": description}
        if rng.random() < 0.7:
            feature["apiAddress"] = f"http://127.0.0.1:{port}/api/"
        if rng.random() < 0.5:
            feature["address"] = f"http://127.0.0.1:{port}/"
        feature["requirement"] = rng.choice(REQUIREMENTS)
        if rng.random() < 0.4:
            feature["documentation"] = f"http://127.0.0.1:{port}/docs"
        feature["keywords"] = keywords
        if rng.random() < 0.15:
            feature["dataRetention"] = rng.choice(RETENTIONS)
        return feature

    def site(self, index: int) -> GeneratedTwin:
        rng = self.rng
        place, city = SITES[index % len(SITES)]
        kind = SITE_KINDS[(index // len(SITES)) % len(SITE_KINDS)]
        number = index // (len(SITES) * len(SITE_KINDS)) + 1
        name = f"{place} {kind}" + (f" {number}" if number > 1 else "")
        dt_id = f"https://dt.example/sites/{_slugish(name)}"
        doc: dict[str, Any] = {
            "version": "1.0",
            "privacy": "public",
            "id": dt_id,
            "name": name,
            "description": f"The {kind} in {place}, {city}. It houses machines and test equipment "
            f"whose twins name it as their parent; "
            f"{' and '.join(self.words_(2))} data of the building is listed here.",
            "owner": f"{city} research campus",
            "contact": {
                "name": f"{kind.capitalize()} manager",
                "email": f"site{index}@twinlink.example",
            },
            "location": {
                "streetAddress": f"{place} {rng.randint(1, 40)}, {city}",
                "gpsCoordinates": f"{rng.uniform(50, 70):.4f}° N, {rng.uniform(4, 30):.4f}° E",
            },
            "features": [
                self._feature(t, kind, ["building", "energy", "safety"])
                for t in rng.sample(FEATURES, rng.randint(3, 6))
            ],
        }
        return GeneratedTwin(dt_id, doc)

    def machine(self, index: int, sites: list[GeneratedTwin]) -> GeneratedTwin:
        """A machine's public part; a quarter also get a group part, a tenth a private part."""
        rng = self.rng
        eq, base_kw = rng.choice(EQUIPMENT)
        maker = rng.choice(MANUFACTURERS)
        site = rng.choice(sites) if sites else None
        place = site.public["name"] if site else rng.choice(SITES)[0]
        dt_id = f"https://dt.example/twins/{_slugish(eq)}-{index:05d}"
        doc = self._machine_doc(index, dt_id, eq, maker, place)
        if rng.random() < 0.6:
            doc["location"] = {"streetAddress": f"{place}, bay {rng.randint(1, 30)}"}
        if site is not None and rng.random() < 0.8:
            doc["relations"] = [{"relationType": "parent", "id": site.key}]
        feats = rng.sample(FEATURES, rng.randint(3, 8))
        doc["features"] = [self._feature(t, eq, base_kw) for t in feats]
        twin = GeneratedTwin(dt_id, doc)
        if rng.random() < 0.25:
            twin.extra_parts.append(self._group_part(dt_id, eq, base_kw))
        if rng.random() < 0.10:
            target = rng.choice(doc["features"])["name"]
            twin.extra_parts.append(_private_part(dt_id, index, target))
        return twin

    def _machine_doc(
        self, index: int, dt_id: str, eq: str, maker: str, place: str
    ) -> dict[str, Any]:
        """The first fields of a machine's public part, up to its manufacturer."""
        rng = self.rng
        code = f"{eq.split()[-1][:3].upper()}-{index:05d}"
        return {
            "version": "1.0",
            "privacy": "public",
            "id": dt_id,
            "name": f"{place.split()[0]} {eq} {code}",
            "description": (
                f"Digital twin of a {maker} {eq} in the {place}. "
                f"{rng.choice(['Used for', 'Serves', 'Runs'])} {' and '.join(self.words_(2))} "
                f"{rng.choice(['experiments', 'production', 'teaching', 'testing'])}; its "
                f"{', '.join(self.words_(3))} data are spread over the systems listed as features."
            ),
            "owner": rng.choice([*OWNERS, f"{maker} service"]),
            "contact": {
                "name": f"{eq.capitalize()} contact",
                "email": f"twin{index}@twinlink.example",
            },
            "manufacturer": maker,
        }

    def _group_part(self, dt_id: str, eq: str, base_kw: list[str]) -> dict[str, Any]:
        rng = self.rng
        group = f"group-{rng.randint(1, 5)}"
        part: dict[str, Any] = {
            "version": "1.0",
            "privacy": group,
            "id": dt_id,
            "contact": {"name": f"{group} lab team", "email": f"{group}@twinlink.example"},
        }
        part["features"] = [self._feature(rng.choice(GROUP_FEATURES), eq, base_kw)]
        return part

    def twins(self, count: int) -> list[GeneratedTwin]:
        """`count` twins: about one site per 50, the sites first."""
        n_sites = max(1, count // 50)
        sites = [self.site(i) for i in range(n_sites)]
        machines = [self.machine(i, sites) for i in range(count - n_sites)]
        return sites + machines

    def queries(self, count: int) -> list[str]:
        """Search text a person would type: common and rare words, two-word queries, prefixes
        of words as they are being typed, and feature names."""
        rng = self.rng
        feature_words = [w.lower() for name, _, _ in FEATURES for w in name.split() if len(w) > 3]
        eq_words = [w.lower() for eq, _ in EQUIPMENT for w in eq.split() if len(w) > 3]
        out = []
        for _ in range(count):
            r = rng.random()
            if r < 0.35:
                q = self.words_(1)[0]
            elif r < 0.55:
                q = " ".join(self.words_(2))
            elif r < 0.70:
                w = rng.choice(self.words)
                q = w[: rng.randint(3, max(3, min(6, len(w))))]
            elif r < 0.80:
                w = rng.choice(self.words)
                q = f"{self.words_(1)[0]} {w[: rng.randint(3, max(3, min(5, len(w))))]}"
            elif r < 0.90:
                q = f"{rng.choice(eq_words)} {rng.choice(feature_words)}"
            elif r < 0.95:
                q = rng.choice(eq_words)
            else:
                q = rng.choice(FIXED_QUERIES)
            out.append(q)
        return out


def _private_part(dt_id: str, index: int, feature: str) -> dict[str, Any]:
    """The private part: the credentials of one of the public features."""
    return {
        "version": "1.0",
        "privacy": "private",
        "id": dt_id,
        "features": [
            {
                "name": feature,
                "requirement": f"Service account 'svc-{index}', password in the lab vault.",
            }
        ],
    }


def _slugish(text: str) -> str:
    ascii_text = unicodedata.normalize("NFKD", text).encode("ascii", "ignore").decode()
    return re.sub(r"[^a-z0-9]+", "-", ascii_text.lower()).strip("-")
