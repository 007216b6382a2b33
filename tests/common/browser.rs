//! A headless Chromium (Debian's, with its chromedriver) driven through WebDriver
//! (fantoccini): pages loaded, JavaScript evaluated, screenshots taken. WebGL draws in
//! software (SwiftShader), so 3D pages render on machines without a GPU.

use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// chromedriver and a headless Chromium session, ended when dropped.
pub struct Browser {
    driver: Child,
    runtime: tokio::runtime::Runtime,
    client: Option<fantoccini::Client>,
}

impl Browser {
    pub fn start(name: &str) -> Browser {
        Browser::with_args(name, &[])
    }

    /// A browser whose pages prefer the dark colour scheme.
    pub fn dark(name: &str) -> Browser {
        Browser::with_args(name, &["--force-dark-mode"])
    }

    pub fn with_args(name: &str, extra: &[&str]) -> Browser {
        let port = {
            let l = std::net::TcpListener::bind("127.0.0.1:0").expect("a free port");
            l.local_addr().expect("port").port()
        };
        let driver = Command::new("chromedriver")
            .arg(format!("--port={port}"))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("chromedriver (Debian's chromium-driver; scripts/test installs it)");
        let profile = super::scratch(&format!("{name}_chromium"));
        let mut args: Vec<String> = [
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            // WebGL in software: three.js pages draw without a GPU.
            "--use-angle=swiftshader",
            "--enable-unsafe-swiftshader",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--window-size=1300,900",
        ]
        .iter()
        .chain(extra)
        .map(|a| a.to_string())
        .collect();
        args.push(format!("--user-data-dir={}", profile.display()));
        let caps: serde_json::Map<String, serde_json::Value> =
            serde_json::from_value(serde_json::json!({ "goog:chromeOptions": {
                "binary": "/usr/bin/chromium",
                "args": args
            }}))
            .expect("capabilities");
        let runtime = tokio::runtime::Runtime::new().expect("runtime");
        let url = format!("http://127.0.0.1:{port}");
        let client = runtime.block_on(async {
            // chromedriver takes a moment to listen.
            for _ in 0..100 {
                let c = fantoccini::ClientBuilder::native()
                    .capabilities(caps.clone())
                    .connect(&url)
                    .await;
                match c {
                    Ok(c) => return c,
                    Err(_) => tokio::time::sleep(Duration::from_millis(100)).await,
                }
            }
            panic!("chromedriver did not answer at {url}");
        });
        Browser {
            driver,
            runtime,
            client: Some(client),
        }
    }

    pub fn goto(&self, url: &str) {
        let c = self.client.as_ref().expect("a session");
        self.runtime.block_on(c.goto(url)).expect("the page loads");
    }

    /// The value of the JavaScript expression `js` in the page.
    pub fn eval(&self, js: &str) -> serde_json::Value {
        let c = self.client.as_ref().expect("a session");
        self.runtime
            .block_on(c.execute(&format!("return {js};"), vec![]))
            .unwrap_or_else(|e| panic!("{js}: {e}"))
    }

    /// A PNG of the window, written to `path` (for docs/; looked at before committing).
    pub fn screenshot(&self, path: &std::path::Path) {
        let c = self.client.as_ref().expect("a session");
        let png = self.runtime.block_on(c.screenshot()).expect("a screenshot");
        std::fs::write(path, png).expect("screenshot written");
    }

    /// A PNG of the element `selector` selects, written to `path` (the window made tall
    /// enough to hold it whole).
    pub fn screenshot_of(&self, selector: &str, path: &std::path::Path) {
        let c = self.client.as_ref().expect("a session");
        let png = self
            .runtime
            .block_on(async {
                c.set_window_size(1300, 1600).await?;
                let e = c.find(fantoccini::Locator::Css(selector)).await?;
                c.execute(
                    "arguments[0].scrollIntoView(true);",
                    vec![serde_json::to_value(&e)?],
                )
                .await?;
                e.screenshot().await
            })
            .unwrap_or_else(|e| panic!("a screenshot of {selector}: {e}"));
        std::fs::write(path, png).expect("screenshot written");
    }

    /// Waits (up to 20 s) until `js` is true in the page.
    pub fn wait_for(&self, js: &str) {
        self.wait_up_to(js, Duration::from_secs(20));
    }

    /// Waits up to `limit` until `js` is true in the page.
    pub fn wait_up_to(&self, js: &str, limit: Duration) {
        let deadline = Instant::now() + limit;
        while self.eval(js) != serde_json::Value::Bool(true) {
            assert!(Instant::now() < deadline, "timed out waiting for: {js}");
            std::thread::sleep(Duration::from_millis(50));
        }
    }
}

impl Drop for Browser {
    fn drop(&mut self) {
        if let Some(c) = self.client.take() {
            let _ = self.runtime.block_on(c.close());
        }
        let _ = self.driver.kill();
        let _ = self.driver.wait();
    }
}
