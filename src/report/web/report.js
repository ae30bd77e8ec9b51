// placeholder: the page helper provides the real report.js
