"""A twin package fetched from the library and made into the resources of one deployment:
its twin.yaml read, its assets resolved and pinned, its parameters checked, its templates
filled."""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Protocol

from twinlink.auth.rights import Principal
from twinlink.deploy.package import PACKAGE_FILE, Package, checked_parameters, parse_package
from twinlink.deploy.plan import ORDER, Resource
from twinlink.deploy.secrets import hidden_values, secret_names
from twinlink.deploy.template import Renderer, Variables, render_all
from twinlink.domain.errors import DocumentError, InvalidInputError, Problem
from twinlink.domain.slug import SLUG
from twinlink.domain.yamlsource import parse_yaml_stream


class Library(Protocol):
    """What deployments use of the library (library/service.py's LibraryService). `Any` for
    its Resolved: it has `.pinned`, `.asset` and `.version.files`."""

    async def resolve(self, principal: Principal, ref: str, *, kind: str | None = None) -> Any: ...
    async def read_text(self, resolved: Any, path: str, max_bytes: int = 1 << 20) -> str: ...
    async def hold(self, holder: str, resolved: Iterable[Any]) -> None: ...
    async def release(self, holder: str) -> None: ...
    async def materialize(self, resolved: Any, dest: Path) -> None: ...


@dataclass(slots=True)
class Loaded:
    """A package ready to apply: what it is, where from, and the resources it makes."""

    package: Package
    resolved: Any  # the package version (library Resolved)
    assets: dict[str, Any]  # alias -> the asset's Resolved
    parameters: dict[str, Any]  # checked, defaults filled in
    resources: list[Resource] = field(default_factory=list)

    @property
    def pinned(self) -> str:
        return str(self.resolved.pinned)

    @property
    def files(self) -> set[str]:
        return {f.path for f in self.resolved.version.files}

    @property
    def secret_names(self) -> frozenset[str]:
        return secret_names(self.package.parameters)

    @property
    def hidden(self) -> frozenset[str]:
        """The secret parameters' values, masked in plans and journals."""
        return hidden_values(self.parameters, self.secret_names)

    def has_phase(self, phase: str) -> bool:
        return f"lifecycle/{phase}" in self.files

    def phases(self) -> frozenset[str]:
        """The lifecycle scripts the package has (lifecycle/<phase>)."""
        return frozenset(
            path.removeprefix("lifecycle/")
            for path in self.files
            if path.startswith("lifecycle/") and path.count("/") == 1
        )


def package_ref(package: str, scope: str | None) -> str:
    """The library ref of a `twins` asset as a deployment names it: `NAME[@REF]`,
    `SCOPE/twins/NAME[@REF]` or a full `lib:` ref; `scope` narrows where a bare name is
    looked up."""
    if not isinstance(package, str) or not package:
        raise InvalidInputError("`package` names a twin package, as tingen-rig@1.0.0")
    if package.startswith("lib:"):
        return package
    parts = package.split("/")
    if len(parts) == 1:
        return f"lib:{scope}/twins/{package}" if scope else f"lib:twins/{package}"
    if len(parts) == 2 and scope:  # twins/NAME
        return f"lib:{scope}/{package}"
    return f"lib:{package}"


def check_name(name: Any) -> str:
    if not isinstance(name, str) or not SLUG.match(name):
        raise InvalidInputError(
            "`name` is the twin's slug: 1-64 lowercase letters, digits and dashes, "
            "starting and ending with a letter or digit"
        )
    return name


@dataclass(frozen=True, slots=True)
class Where:
    """What the templates may name besides parameters and assets."""

    name: str
    twin_url: str
    server_url: str


async def load(
    library: Library,
    principal: Principal,
    ref: str,
    parameters: Any,
    where: Where,
) -> Loaded:
    """The package at `ref` made into `where.name`'s resources; 422 naming what is wrong."""
    resolved = await library.resolve(principal, ref, kind="twins")
    files = {f.path for f in resolved.version.files}
    if PACKAGE_FILE not in files:
        raise InvalidInputError(f"{resolved.pinned} has no {PACKAGE_FILE}: not a twin package")
    package = parse_package(await library.read_text(resolved, PACKAGE_FILE))
    params = checked_parameters(package.parameters, parameters)
    assets = {
        alias: await library.resolve(principal, asset_ref)
        for alias, asset_ref in package.assets.items()
    }
    loaded = Loaded(package, resolved, assets, params)
    loaded.resources = await _render(library, loaded, where)
    return loaded


async def _render(library: Library, loaded: Loaded, where: Where) -> list[Resource]:
    package = loaded.package
    variables = Variables(
        loaded.parameters,
        {
            "deployment.name": where.name,
            "twin.slug": where.name,
            "twin.url": where.twin_url,
            "server.url": where.server_url,
            **{f"assets.{alias}": r.pinned for alias, r in loaded.assets.items()},
        },
    )
    main = Renderer(variables, package.source, "")
    if isinstance(package.document, str):
        doc_renderer, document = await _document_file(library, loaded, package.document, variables)
    else:
        doc_renderer = main
        raw = package.document or {"version": "1.0", "name": where.name,
                                   "description": package.description}  # fmt: skip
        document = main.render(raw, ("document",))
    rendered = {kind: main.render(getattr(package, kind), (kind,)) for kind in
                ("devices", "services", "processors", "connectors")}  # fmt: skip
    render_all([main] if doc_renderer is main else [main, doc_renderer])
    out = [Resource("twin", where.name, document)]
    for kind in ORDER[1:]:
        for i, item in enumerate(rendered[kind + "s"]):
            name = item.get("name")
            if not isinstance(name, str) or not name:
                raise DocumentError(
                    "A resource's name is not text once filled in; nothing was deployed.",
                    [package.source.problem("a name must be text", (kind + "s", i, "name"))],
                )
            spec = dict(item)
            if kind == "device":
                spec.setdefault("description", "")
            out.append(Resource(kind, name, spec))
    return out


async def _document_file(
    library: Library, loaded: Loaded, path: str, variables: Variables
) -> tuple[Renderer, Any]:
    if path not in loaded.files:
        raise DocumentError(
            "The twin package's document is missing; nothing was deployed.",
            [Problem(f"document: no file {path!r} in the package", "document")],
        )
    docs = parse_yaml_stream(await library.read_text(loaded.resolved, path))
    if len(docs) != 1:
        raise DocumentError(
            "The twin package's document must be one YAML document; nothing was deployed.",
            [Problem(f"{path} holds {len(docs)} documents", "document")],
        )
    renderer = Renderer(variables, docs[0], path)
    return renderer, renderer.render(docs[0].data)
