// The token lives in sessionStorage: it is gone when the tab closes and never sent anywhere
// but this server's API.
(function () {
  const KEY = "twinlink.token";
  const form = document.getElementById("signin");
  const error = document.getElementById("error");

  function show(token) {
    form.hidden = true;
    document.getElementById("signout").hidden = false;
    if (typeof SwaggerUIBundle === "undefined") {
      // /docs/assets/ answered that the viewer is not built (the web app's build holds it).
      document.getElementById("swagger-ui").textContent =
        "The API viewer is not built: run make setup (or npm run build in ui/). " +
        "The API description itself is at /openapi.json.";
      return;
    }
    const ui = SwaggerUIBundle({
      url: "/openapi.json",
      dom_id: "#swagger-ui",
      persistAuthorization: false,
      // Tags collapsed: the API has well over 100 operations, and a tag's list is what a
      // reader opens (Swagger UI renders a long list only as far as it is scrolled).
      docExpansion: "none",
      requestInterceptor: function (req) {
        if (!req.headers.Authorization) req.headers.Authorization = "Bearer " + token;
        return req;
      },
      // The token the page signed in with is the one "Try it out" sends (Authorize changes it).
      onComplete: function () { ui.preauthorizeApiKey("HTTPBearer", token); },
    });
  }

  async function signIn(event) {
    event.preventDefault();
    error.textContent = "";
    let token = document.getElementById("token").value.trim();
    if (!token) {
      const r = await fetch("/api/v1/auth/login", {
        method: "POST",
        headers: {"Content-Type": "application/json"},
        body: JSON.stringify({
          username: document.getElementById("username").value,
          password: document.getElementById("password").value,
        }),
      });
      const body = await r.json();
      if (!r.ok) { error.textContent = body.detail || "Sign-in failed"; return; }
      token = body.token;
    }
    const check = await fetch("/api/v1/auth/me", {headers: {Authorization: "Bearer " + token}});
    if (!check.ok) { error.textContent = "The token is not valid."; return; }
    sessionStorage.setItem(KEY, token);
    show(token);
  }

  document.getElementById("signout").onclick = function () {
    sessionStorage.removeItem(KEY);
    location.reload();
  };
  form.addEventListener("submit", signIn);
  const saved = sessionStorage.getItem(KEY);
  if (saved) show(saved); else form.hidden = false;
})();
