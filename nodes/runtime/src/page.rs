//! The built-in page (issue 14): a small HTTP server that hands out one HTML page and its
//! script (compiled into the binary: nothing is fetched at run time). The page connects to the
//! live feed ([`crate::live`]) and draws the machine from it.
//!
//! Plain HTTP/1.1, GET only, one response per connection: the page is two files, so a
//! framework would add more than it saves.

use std::net::SocketAddr;
use tokio::io::{AsyncReadExt, AsyncWriteExt};

const INDEX: &str = include_str!("../web/index.html");
const SCRIPT: &str = include_str!("../web/app.js");
const CDR: &str = include_str!("../web/cdr.js");

/// Starts serving the page on `host:port` (0 = any free port); the page connects to the feed
/// on `feed_port` of the host it was loaded from.
pub(crate) async fn serve(host: &str, port: u16, feed_port: u16) -> std::io::Result<SocketAddr> {
    let listener = tokio::net::TcpListener::bind((host, port)).await?;
    let addr = listener.local_addr()?;
    let index = INDEX.replace("{{FEED_PORT}}", &feed_port.to_string());
    tokio::spawn(async move {
        loop {
            let Ok((stream, _)) = listener.accept().await else {
                continue;
            };
            let index = index.clone();
            tokio::spawn(async move {
                let _ = respond(stream, &index).await;
            });
        }
    });
    Ok(addr)
}

/// Reads one request and answers it.
async fn respond(mut stream: tokio::net::TcpStream, index: &str) -> std::io::Result<()> {
    let mut buf = Vec::with_capacity(1024);
    let mut chunk = [0u8; 1024];
    // The request head, at most 16 KiB, read within 5 s.
    let read = tokio::time::timeout(std::time::Duration::from_secs(5), async {
        while !buf.windows(4).any(|w| w == b"\r\n\r\n") && buf.len() < 16 * 1024 {
            let n = stream.read(&mut chunk).await?;
            if n == 0 {
                break;
            }
            buf.extend_from_slice(&chunk[..n]);
        }
        Ok::<_, std::io::Error>(())
    })
    .await;
    if !matches!(read, Ok(Ok(()))) {
        return Ok(());
    }
    let head = String::from_utf8_lossy(&buf);
    let mut words = head.split_whitespace();
    let (method, target) = (words.next().unwrap_or(""), words.next().unwrap_or(""));
    let path = target.split('?').next().unwrap_or("");
    let (status, kind, body) = match (method, path) {
        ("GET", "/" | "/index.html") => ("200 OK", "text/html; charset=utf-8", index),
        ("GET", "/app.js") => ("200 OK", "text/javascript; charset=utf-8", SCRIPT),
        ("GET", "/cdr.js") => ("200 OK", "text/javascript; charset=utf-8", CDR),
        ("GET", _) => ("404 Not Found", "text/plain; charset=utf-8", "not found\n"),
        _ => (
            "405 Method Not Allowed",
            "text/plain; charset=utf-8",
            "GET only\n",
        ),
    };
    let reply = format!(
        "HTTP/1.1 {status}\r\nContent-Type: {kind}\r\nContent-Length: {}\r\nCache-Control: no-store\r\nConnection: close\r\n\r\n{body}",
        body.len()
    );
    stream.write_all(reply.as_bytes()).await?;
    stream.shutdown().await
}
